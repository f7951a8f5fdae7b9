"""The co-simulation service's small parts: results read back for a chart (decimated, a
running file's unfinished line left), result columns as signal names, the settings' checks,
and a worker a killed server left behind killed at the next start (only if it is that one)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from twinlink.cosim import params
from twinlink.cosim.outputs import signal_of
from twinlink.cosim.recovery import kill_leftover, note_worker
from twinlink.cosim.resultfile import read_columns
from twinlink.domain.errors import InvalidInputError


def _csv(path: Path, rows: int, tail: str = "") -> None:
    lines = ["time,{a}.m.x,b.y"] + [f"{i * 0.1!r},{float(i)!r},{-float(i)!r}" for i in range(rows)]
    path.write_text("\n".join(lines) + "\n" + tail, encoding="utf-8")


def test_results_are_column_by_column_and_picked_evenly_with_the_first_and_last(
    tmp_path: Path,
) -> None:
    path = tmp_path / "outputs.csv"
    _csv(path, 1001)
    got = read_columns(path, 11)
    assert got["columns"] == ["time", "{a}.m.x", "b.y"]
    assert got["data"][1] == [float(i) for i in range(0, 1001, 100)]
    assert got["data"][2][-1] == -1000.0
    whole = read_columns(path, 2000)
    assert len(whole["data"][0]) == 1001 and whole["data"][0][:2] == [0.0, 0.1]


def test_a_running_files_unfinished_line_waits_and_nan_is_null(tmp_path: Path) -> None:
    path = tmp_path / "outputs.csv"
    _csv(path, 3, tail="0.30000000000000004,3.0,-3")
    assert read_columns(path, 100)["data"][1] == [0.0, 1.0, 2.0]
    path.write_text("time,x\n0.0,nan\n", encoding="utf-8")
    assert read_columns(path, 100)["data"] == [[0.0], [None]]
    assert read_columns(tmp_path / "none.csv", 10) == {"columns": [], "data": []}
    (tmp_path / "header.csv").write_text("time,x\n", encoding="utf-8")
    assert read_columns(tmp_path / "header.csv", 10) == {"columns": ["time", "x"], "data": [[], []]}


def test_result_columns_become_signal_names() -> None:
    assert signal_of("{msd1}.m1.x1") == "msd1.m1.x1"
    assert signal_of("plant.der(T)") == "plant.der_T_"
    assert signal_of("body.r[1]") == "body.r_1_"


@pytest.mark.parametrize(
    ("check", "value", "word"),
    [
        (params.check_mode, "fast", "batch or realtime"),
        (params.check_factor, 0.0, "above 0"),
        (params.check_factor, float("nan"), "above 0"),
        (params.check_factor, 1e9, "at most"),
        (params.check_prefix, "1x", "signal name"),
        (params.check_stream, "Cosim Out", "stream name"),
        (params.check_name, "tab\there", "printable"),
    ],
)
def test_settings_are_refused_saying_what_to_send(check: object, value: object, word: str) -> None:
    with pytest.raises(InvalidInputError, match=word):
        check(value)  # type: ignore[operator]


def test_the_settings_defaults() -> None:
    assert (params.check_name(None), params.check_stream(None)) == ("cosim", "cosim")
    assert params.check_prefix("") == "" and params.check_prefix("sim.") == "sim."


def test_a_leftover_worker_is_killed_only_where_it_worked(tmp_path: Path) -> None:
    results, elsewhere = tmp_path / "results", tmp_path / "other"
    results.mkdir()
    elsewhere.mkdir()
    sleeper = [sys.executable, "-c", "import time; time.sleep(60)"]
    worker = subprocess.Popen(sleeper, cwd=results, start_new_session=True)
    stranger = subprocess.Popen(sleeper, cwd=elsewhere, start_new_session=True)
    try:
        note_worker(results, worker.pid)
        (results / "worker.pid").write_text(f"{stranger.pid}\n")  # a pid reused elsewhere
        kill_leftover(results)
        assert stranger.poll() is None  # another folder's process: left alone
        note_worker(results, worker.pid)
        kill_leftover(results)
        assert worker.wait(timeout=10) == -9
        kill_leftover(tmp_path / "nothing-here")  # no note: nothing to do
    finally:
        for proc in (worker, stranger):
            proc.kill()
            proc.wait()
