"""A co-simulation run in its own process (cosim/worker.py), driven from the server's side
(cosim/jobs.py), on the mass-spring-damper FMUs: batch (columns, progress, rows, the CSV as
runner.run writes it), paced to the wall clock, stopped, killed, cancelled, an FMU that
fails and one that crashes its process. Nothing here asserts how long anything took."""

from __future__ import annotations

import asyncio
import csv
import io
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import orjson
import psutil
import pytest

from tests.conftest import FmuFiles
from twinlink.cosim.jobs import CosimJob, JobSpec, worker_environment
from twinlink.cosim.model import Algorithm, System
from twinlink.cosim.runner import run
from twinlink.cosim.worker import Rows
from twinlink.cosim.yamlform import read_yaml

pytestmark = pytest.mark.integration

MSD = """\
instances:
  mass: mass.fmu
  spring: spring.fmu
  {extra}
connections:
  mass.x1: [spring.x1{x1_to}]
  mass.v1: [spring.v1{v1_to}]
  spring.fk: mass.fk
parameters:
  mass.x1: 1.0
  {parameters}
log:
  mass: [x1, v1]
  spring: [fk]
algorithm:
  type: fixed-step
  size: {step}
start_time: 0
end_time: {end}
"""
COLUMNS = ["time", "mass.x1", "mass.v1", "spring.fk"]


@pytest.fixture(scope="module")
def fmus(fmu_files: FmuFiles) -> dict[str, Path]:
    return {
        "mass.fmu": fmu_files("msd_mass"),
        "spring.fmu": fmu_files("msd_spring"),
        "status.fmu": fmu_files("status"),
        "crash.fmu": fmu_files("crash"),
    }


def document(
    tmp_path: Path,
    *,
    step: float = 0.01,
    end: float = 10.0,
    extra: str = "",
    x1_to: str = "",
    v1_to: str = "",
    parameters: str = "",
) -> Path:
    """The msd pair as a YAML document; `extra` an instance added to it (YAML), `x1_to` and
    `v1_to` more inputs fed by the mass's position and speed, `parameters` one more."""
    path = tmp_path / "system.yaml"
    path.write_text(
        MSD.format(
            step=step,
            end=end,
            extra=extra,
            x1_to=f", {x1_to}" if x1_to else "",
            v1_to=f", {v1_to}" if v1_to else "",
            parameters=parameters,
        )
    )
    return path


@dataclass
class Seen:
    """What a job's callbacks were given."""

    columns: list[list[str]] = field(default_factory=list)
    progress: list[tuple[float, float]] = field(default_factory=list)
    batches: list[np.ndarray] = field(default_factory=list)
    some_rows: asyncio.Event = field(default_factory=asyncio.Event)

    @property
    def rows(self) -> np.ndarray:
        return np.vstack(self.batches) if self.batches else np.empty((0, 0))

    def job(self, spec: JobSpec, **kwargs: Any) -> CosimJob:
        async def on_rows(rows: np.ndarray) -> None:  # a coroutine, as the service's is
            self.batches.append(rows)
            self.some_rows.set()

        return CosimJob(
            spec,
            on_columns=self.columns.append,
            on_progress=lambda f, t: self.progress.append((f, t)),
            on_rows=on_rows,
            **kwargs,
        )


def spec_of(doc: Path, fmus: dict[str, Path], **kwargs: Any) -> JobSpec:
    return JobSpec(
        document=doc, format="yaml", fmu_paths=fmus, csv=doc.parent / "out.csv", **kwargs
    )


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    with path.open(newline="") as file:
        header, *rows = list(csv.reader(file))
    return header, np.array([[float(v) for v in row] for row in rows]).reshape(-1, len(header))


async def run_job(spec: JobSpec, **kwargs: Any) -> tuple[str, str, Seen]:
    seen = Seen()
    job = seen.job(spec, **kwargs)
    await job.start()
    end, message = await job.wait()
    return end, message, seen


async def test_a_batch_run_reports_as_it_goes_and_writes_the_csv_runner_run_writes(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(tmp_path, step=0.001, end=10.0)  # 10 000 steps
    spec = spec_of(doc, fmus)
    end, message, seen = await run_job(spec)
    assert (end, message.split(" in ")[0]) == ("finished", "10000 steps")
    assert seen.columns == [COLUMNS]
    # The CSV is the one runner.run writes for the same system, to the last digit...
    expected = run(read_yaml(doc), fmus)
    text = io.StringIO()
    expected.write_csv(text)
    assert spec.csv.read_text() == text.getvalue()
    # ...and the streamed rows are its rows, in batches of at most 1000.
    assert np.array_equal(seen.rows, expected.values)
    assert len(seen.batches) >= 11 and max(len(b) for b in seen.batches) <= 1000
    # Progress goes up, at most about 100 times, and ends at 1.0 at the end time.
    fractions = [f for f, _ in seen.progress]
    assert fractions == sorted(fractions) and len(fractions) <= 102
    assert seen.progress[-1] == (1.0, 10.0)
    assert all(f == pytest.approx(t / 10.0) for f, t in seen.progress)


def test_the_worker_speaks_json_lines_columns_first_and_the_end_last(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    spec = spec_of(document(tmp_path, step=0.01, end=2.0), fmus, stream=False)
    env = worker_environment(tmp_path)
    done = subprocess.run(
        [sys.executable, "-m", "twinlink.cosim.worker"], input=spec.to_json(),
        capture_output=True, env=env, cwd=tmp_path, timeout=120, check=True,
    )  # fmt: skip
    lines = [orjson.loads(line) for line in done.stdout.splitlines()]
    in_process = ["instance 'mass' (mass.fmu)", "instance 'spring' (spring.fmu)"]
    assert lines[:2] == [{"in_process": in_process}, {"columns": COLUMNS}]
    assert lines[-1] == {"end": "finished", "message": lines[-1]["message"]}
    assert lines[-2] == {"progress": 1.0, "time": 2.0}
    assert all(set(line) == {"progress", "time"} for line in lines[2:-1])  # no rows asked for
    _, rows = read_csv(spec.csv)
    assert len(rows) == 201


@pytest.mark.parametrize(
    ("job", "why"),
    [
        (b"{not json", "unexpected character"),
        (b'{"format": "yaml"}', "it has no 'document'"),
        (b'{"document": "d", "format": "x", "fmu_paths": {}, "csv": "c"}', "format must be"),
        (
            b'{"document": "d", "format": "yaml", "fmu_paths": {}, "csv": "c", "factor": -1}',
            "the real-time factor must be a positive number, not -1",
        ),
    ],
)
def test_a_job_that_cannot_be_read_is_a_failed_run(tmp_path: Path, job: bytes, why: str) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "twinlink.cosim.worker"], input=job, capture_output=True,
        env=worker_environment(tmp_path), cwd=tmp_path, timeout=120, check=True,
    )  # fmt: skip
    (line,) = [orjson.loads(line) for line in done.stdout.splitlines()]
    assert line["end"] == "failed"
    assert line["message"].startswith("the job cannot be read: ") and why in line["message"]


# The worker, with the run printing on file descriptor 1 as an FMU's printf would.
NOISY_WORKER = """
import os, sys
from twinlink.cosim import worker
ran = worker.run
def run(*args):
    os.write(1, b"native noise without a newline")
    print("print() from Python")
    return ran(*args)
worker.run = run
sys.exit(worker.main())
"""


def test_what_fmus_print_goes_to_stderr_not_between_the_lines(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    spec = spec_of(document(tmp_path, step=0.01, end=1.0), fmus)
    done = subprocess.run(
        [sys.executable, "-c", NOISY_WORKER], input=spec.to_json(), capture_output=True,
        env=worker_environment(tmp_path), cwd=tmp_path, timeout=120, check=True,
    )  # fmt: skip
    lines = [orjson.loads(line) for line in done.stdout.splitlines()]
    assert lines[-1]["end"] == "finished"
    assert sum(len(line.get("rows", [])) for line in lines) == 101
    assert b"native noise without a newline" in done.stderr
    assert b"print() from Python" in done.stderr


async def test_a_realtime_run_gives_the_batch_results_and_its_jitter(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(tmp_path, step=0.01, end=5.0)
    end, message, seen = await run_job(spec_of(doc, fmus, mode="realtime", factor=50.0))
    assert end == "finished"
    assert message.startswith("real time x50: 500 steps, start jitter p50 ")
    assert np.array_equal(seen.rows, run(read_yaml(doc), fmus).values)
    assert seen.progress[-1] == (1.0, 5.0)


async def test_a_stopped_run_ends_after_its_step_and_keeps_every_row(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(tmp_path, step=0.01, end=1000.0)  # 1000 s in real time: stopped long before
    spec = spec_of(doc, fmus, mode="realtime", factor=1.0, batch_ms=20)
    seen = Seen()
    job = seen.job(spec)
    await job.start()
    waiting = asyncio.create_task(job.wait())
    await asyncio.wait_for(seen.some_rows.wait(), 60)
    await job.stop()
    end, message = await waiting
    stopped_at = float(seen.rows[-1, 0])
    assert (end, message) == ("stopped", f"stopped at t = {stopped_at:g} s")
    assert 0 < stopped_at < 1000
    header, rows = read_csv(spec.csv)
    assert header == COLUMNS
    assert np.array_equal(rows, seen.rows)  # the CSV holds every row computed, no more
    assert rows[:, 0] == pytest.approx(np.arange(len(rows)) * 0.01)
    assert seen.progress[-1] == (pytest.approx(stopped_at / 1000), stopped_at)


async def test_a_run_that_does_not_stop_in_time_is_killed_with_its_rows_so_far(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(tmp_path, step=0.01, end=1000.0)
    spec = spec_of(doc, fmus, mode="realtime", factor=1.0, batch_ms=20)
    seen = Seen()
    job = seen.job(spec, grace_s=0.0)  # no time at all to end its step
    await job.start()
    waiting = asyncio.create_task(job.wait())
    await asyncio.wait_for(seen.some_rows.wait(), 60)
    await job.stop()
    end, message = await waiting
    assert end == "stopped"
    assert message.startswith("killed after 0 s: it did not end its step at t = ")
    _, rows = read_csv(spec.csv)
    assert len(rows) >= len(seen.batches[0])  # what was flushed before the kill stays
    assert job.pid is not None
    with pytest.raises(ProcessLookupError):
        os.kill(job.pid, 0)


async def test_cancelling_the_wait_stops_the_process(tmp_path: Path, fmus: dict[str, Path]) -> None:
    spec = spec_of(document(tmp_path, end=1000.0), fmus, mode="realtime")
    seen = Seen()
    job = seen.job(spec)
    await job.start()
    waiting = asyncio.create_task(job.wait())
    await asyncio.wait_for(seen.some_rows.wait(), 60)
    waiting.cancel()
    with pytest.raises(asyncio.CancelledError):
        await waiting
    assert job.pid is not None
    with pytest.raises(ProcessLookupError):
        os.kill(job.pid, 0)


def first_time(doc: Path, fmus: dict[str, Path], column: str, when: Callable[[Any], Any]) -> float:
    """The first time `when(column)` holds in the msd pair run alone."""
    clean = run(read_yaml(document(doc.parent / "clean")), fmus)
    return float(clean.column("time")[np.argmax(when(clean.column(column)))])


async def test_an_fmu_that_fails_ends_the_run_failed_naming_it_with_the_rows_before(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    # status.fmu refuses a negative input: it fails once mass.x1 goes below 0.
    doc = document(tmp_path, extra="bad: status.fmu", x1_to="bad.u")
    spec = spec_of(doc, fmus)
    end, message, seen = await run_job(spec)
    (tmp_path / "clean").mkdir()
    # Gauss-Seidel: bad steps after the mass, from the mass's x1 at the step's end.
    fails_at = round(first_time(doc, fmus, "mass.x1", lambda x: x < 0) - 0.01, 9)
    assert end == "failed"
    assert message.startswith(
        f"instance 'bad' (status.fmu): fmi2DoStep returned error at t = {fails_at:g} s"
    )
    assert "negative input u=" in message
    _, rows = read_csv(spec.csv)
    assert rows[-1, 0] == pytest.approx(fails_at)  # every row before the failing step
    assert np.array_equal(rows, seen.rows)


async def test_a_crashing_fmu_fails_the_run_with_the_signal_and_its_stack(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    # crash.fmu writes through NULL once its input passes its threshold. Paced at x10, the
    # run has rows flushed before it crashes (each 50 ms of wall time).
    doc = document(
        tmp_path, extra="boom: crash.fmu", v1_to="boom.u", parameters="boom.threshold: 0.2"
    )
    spec = spec_of(doc, fmus, mode="realtime", factor=10.0)
    end, message, seen = await run_job(spec)
    (tmp_path / "clean").mkdir()
    crashes_at = first_time(doc, fmus, "mass.v1", lambda v: v > 0.2)
    assert end == "failed"
    assert message.startswith("the co-simulation process crashed at t = ")
    assert (
        "(killed by signal SIGSEGV (Segmentation fault)), in the native code of one of "
        "the FMUs it runs itself (instance 'mass' (mass.fmu), instance 'spring' "
        "(spring.fmu), instance 'boom' (crash.fmu)); run them with isolated: true" in message
    )
    assert "Fatal Python error: Segmentation fault" in message  # faulthandler's stack
    _, rows = read_csv(spec.csv)
    assert len(rows) > 1 and rows[-1, 0] <= crashes_at
    assert np.array_equal(rows, seen.rows[: len(rows)])


async def test_a_crash_of_the_only_fmu_the_worker_runs_itself_names_it(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(
        tmp_path,
        extra="boom: crash.fmu",
        parameters="boom.u: 1.0\n  boom.threshold: 0.5",  # crashes at its first step
    ).read_text()
    isolated = doc.replace("mass: mass.fmu", "mass: {fmu: mass.fmu, isolated: true}")
    isolated = isolated.replace("spring: spring.fmu", "spring: {fmu: spring.fmu, isolated: true}")
    (tmp_path / "system.yaml").write_text(isolated)
    spec = spec_of(tmp_path / "system.yaml", fmus)
    end, message, _ = await run_job(spec)
    assert end == "failed"
    assert (
        "(killed by signal SIGSEGV (Segmentation fault)), in the native code of "
        "instance 'boom' (crash.fmu); its last output:" in message
    )
    header, rows = read_csv(spec.csv)
    assert header == COLUMNS and len(rows) <= 1  # the header at once; the rows each batch


async def test_a_crash_in_an_isolated_instance_fails_the_run_naming_it(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = document(
        tmp_path,
        extra="boom: {fmu: crash.fmu, isolated: true}",
        v1_to="boom.u",
        parameters="boom.threshold: 0.2",
    )
    spec = spec_of(doc, fmus)
    end, message, seen = await run_job(spec)
    assert end == "failed"
    assert message.startswith("instance 'boom' (crash.fmu): its process (pid ")
    assert "SIGSEGV" in message
    _, rows = read_csv(spec.csv)
    assert np.array_equal(rows, seen.rows) and len(rows) > 1  # the worker itself lived on


async def test_a_stopped_run_with_an_isolated_instance_stops_and_leaves_no_process(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    # The stop is the worker's alone (its isolated instance's process is its to close): the
    # run stops, not fails; the test's hygiene checks no process is left.
    doc = document(
        tmp_path, end=1000.0, extra="boom: {fmu: crash.fmu, isolated: true}", v1_to="boom.u"
    )
    spec = spec_of(doc, fmus, mode="realtime", factor=1.0, batch_ms=20)
    seen = Seen()
    job = seen.job(spec)
    await job.start()
    waiting = asyncio.create_task(job.wait())
    await asyncio.wait_for(seen.some_rows.wait(), 60)
    await job.stop()
    end, message = await waiting
    assert end == "stopped" and message.startswith("stopped at t = ")
    _, rows = read_csv(spec.csv)
    assert np.array_equal(rows, seen.rows)


async def test_what_the_run_did_not_do_as_the_file_asked_is_in_its_message(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    # status.fmu cannot save its state: the var-step master cannot reject a step.
    doc = document(tmp_path, end=1.0, extra="bad: status.fmu", x1_to="bad.u")
    doc.write_text(
        doc.read_text().replace(
            "type: fixed-step\n", "type: var-step\n  min_size: 0.001\n  max_size: 0.1\n"
        )
    )
    end, message, seen = await run_job(spec_of(doc, fmus))
    assert end == "finished"
    assert message.startswith(f"{len(seen.rows) - 1} steps in ")
    assert "; not every instance can save and restore its state" in message


async def test_a_document_that_cannot_be_read_fails_the_run_saying_where(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    doc = tmp_path / "system.yaml"
    doc.write_text("instances:\n  mass: mass.fmu\nconections: {}\n")
    end, message, seen = await run_job(spec_of(doc, fmus))
    assert end == "failed"
    assert str(doc) in message and "conections" in message
    assert seen.columns == [] and seen.batches == []


async def test_a_worker_that_cannot_start_is_a_failed_run(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    spec = spec_of(document(tmp_path), fmus)
    end, message, _ = await run_job(spec, python=str(tmp_path / "no-python"))
    assert end == "failed" and message.startswith("could not start: ")


class FakeOutput:
    def __init__(self) -> None:
        self.sent: list[dict[str, Any]] = []

    def send(self, message: dict[str, Any]) -> None:  # as Output writes it: at once
        self.sent.append(orjson.loads(orjson.dumps(message, option=orjson.OPT_SERIALIZE_NUMPY)))


@pytest.mark.parametrize("mode", ["batch", "realtime"])
def test_rows_go_out_in_batches_of_wall_time_and_progress_as_it_moves(mode: str) -> None:
    # An open-ended system (no end time: no fraction of a span to tell), a row every 10 ms
    # of a fake clock for 3 s, batches of 50 ms.
    system = System((), (), {}, {}, Algorithm("fixed-step", 0.01), end_time=None)
    session = SimpleNamespace(system=system, columns=("time", "x"))
    spec = JobSpec(Path("d.yaml"), "yaml", {}, Path("out.csv"), mode=mode, batch_ms=50)  # type: ignore[arg-type]
    now = [0]
    out, text = FakeOutput(), io.StringIO()
    rows = Rows(spec, session, out, text, clock=lambda: now[0])  # type: ignore[arg-type]
    for k in range(301):
        rows.add(np.array([k * 0.01, float(k)]))
        now[0] += 10_000_000
    rows.flush(last=True)
    batches = [m["rows"] for m in out.sent if "rows" in m]
    assert [len(b) for b in batches] == [6] * 50 + [1]  # 50 ms after each batch's first row
    assert np.array_equal(np.vstack(batches)[:, 1], np.arange(301))
    assert text.getvalue().splitlines()[:3] == ["time,x", "0.0,0.0", "0.01,1.0"]
    told = [m["time"] for m in out.sent if "progress" in m]
    if mode == "batch":  # no span: the first and the last only
        assert told == [0.05, 3.0]
    else:  # real time: once a second of wall time too
        assert told == [0.05, 1.07, 2.09, 3.0]  # the first batch ending 1 s after the last


# A server: starts the worker with its output to a pipe only it reads, gives it its job,
# says the worker's pid, and waits to be killed.
SERVER = """
import subprocess, sys, time
worker = subprocess.Popen([sys.executable, "-m", "twinlink.cosim.worker"],
                          stdin=subprocess.PIPE, stdout=subprocess.PIPE)
worker.stdin.write(open(sys.argv[1], "rb").read())
worker.stdin.close()
print(worker.pid, flush=True)
worker.stdout.readline()
time.sleep(600)
"""


def test_a_run_whose_server_died_stops_at_its_next_line(
    tmp_path: Path, fmus: dict[str, Path]
) -> None:
    # 1000 s in real time, no rows sent: the worker writes its progress once a second.
    spec = spec_of(document(tmp_path, end=1000.0), fmus, mode="realtime", stream=False)
    (tmp_path / "job.json").write_bytes(spec.to_json())
    server = subprocess.Popen(
        [sys.executable, "-c", SERVER, str(tmp_path / "job.json")],
        stdout=subprocess.PIPE, env=worker_environment(tmp_path), cwd=tmp_path,
    )  # fmt: skip
    assert server.stdout is not None
    worker = psutil.Process(int(server.stdout.readline()))
    server.stdout.close()
    wait_for(lambda: spec.csv.exists() and spec.csv.read_text().count("\n") > 2, "some rows")
    server.kill()
    server.wait()
    wait_for(lambda: not _alive(worker), "the worker to end")
    header, rows = read_csv(spec.csv)  # closed with every row it computed
    assert header == COLUMNS
    assert rows[:, 0] == pytest.approx(np.arange(len(rows)) * 0.01)


def _alive(process: psutil.Process) -> bool:
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def wait_for(condition: Callable[[], bool], what: str, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)


def test_the_worker_gets_none_of_the_servers_settings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TWINLINK_SECRET_KEY", "s3cret")
    monkeypatch.setenv("TWINLINK_DATABASE_URL", "postgresql://u:pw@db/twinlink")
    env = worker_environment(tmp_path)
    assert not [k for k in env if k.startswith("TWINLINK_")]
    assert "s3cret" not in env.values()
    assert env["HOME"] == str(tmp_path) and env["PATH"] == os.environ["PATH"]
