"""`twinlink cosim run` and `check` as a person runs them: the real command as a subprocess on
the example (examples/cosim, its FMUs built by its build.sh), the CSV, progress, the mistakes
said in one line with their exit status, a real-time run stopped by SIGTERM as a deployment
stops its execute phase, and the rows sent as a device's samples to a real server."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import zipfile
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pytest

from tests.conftest import EXAMPLES, ROOT, Server
from tests.integration._device import make_twin
from tests.integration._util import poll_until
from twinlink.cli.cosimsend import DeviceSender

pytestmark = pytest.mark.integration

EXAMPLE = EXAMPLES / "cosim"
HEADER = ["time", "{msd1}.msd1i.x1", "{msd1}.msd1i.v1", "{msd2}.msd2i.x2", "{msd2}.msd2i.v2",
          "{msd2}.msd2i.fk"]  # fmt: skip
SIGNALS = ["msd1.msd1i.x1", "msd1.msd1i.v1", "msd2.msd2i.x2", "msd2.msd2i.v2", "msd2.msd2i.fk"]


@dataclass
class Done:
    code: int
    out: str
    err: str

    def ok(self) -> Done:
        assert self.code == 0, self.err
        assert "Traceback" not in self.err
        return self


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("TWINLINK_")}
    return {**env, "NO_COLOR": "1", **extra}


def twinlink(*args: str, cwd: Path, **env: str) -> Done:
    p = subprocess.run([sys.executable, "-m", "twinlink", *args], cwd=cwd, env=_env(**env),
                       capture_output=True, text=True, timeout=120)  # fmt: skip
    return Done(p.returncode, p.stdout, p.stderr)


@pytest.fixture(scope="module")
def example(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The example folder as its README makes it: the FMUs built by build.sh beside msd.json."""
    folder = tmp_path_factory.mktemp("example")
    shutil.copyfile(EXAMPLE / "msd.json", folder / "msd.json")
    built = subprocess.run(["sh", str(EXAMPLE / "build.sh"), str(folder)], capture_output=True,
                           text=True, timeout=300, env=_env(PYTHON=sys.executable))  # fmt: skip
    assert built.returncode == 0, built.stderr
    assert {p.name for p in folder.iterdir()} == {
        "msd.json", "MassSpringDamper1.fmu", "MassSpringDamper2.fmu"
    }  # fmt: skip
    return folder


def _rows(text: str) -> list[list[str]]:
    return list(csv.reader(io.StringIO(text)))


def test_run_writes_maestros_csv_and_says_its_progress(example: Path) -> None:
    done = twinlink("cosim", "run", "msd.json", cwd=example).ok()
    rows = _rows(done.out)
    assert rows[0] == HEADER
    assert len(rows) == 1 + 1001  # 0 to 10 s by 0.01 s
    assert [float(r[0]) for r in rows[1:4]] == [0.0, 0.01, 0.02]
    assert float(rows[-1][0]) == 10.0
    assert rows[1][1:3] == ["1.0", "0.0"]  # x1 starts at its parameter, at rest
    # the coupled pair moves the second mass, and the damping shrinks the first's swing
    assert max(abs(float(r[3])) for r in rows[1:]) > 0.1
    assert abs(float(rows[-1][1])) < 1.0
    progress = [line for line in done.err.splitlines() if "%" in line]
    assert len(progress) == 9 and progress[0] == "msd.json:  10%  t = 1 s"
    assert done.err.splitlines()[-1].startswith("msd.json: finished: 1001 rows to t = 10 s in ")

    again = twinlink("cosim", "run", "msd.json", "-o", "out.csv", "--end", "2", "--step", "0.1",
                     cwd=example).ok()  # fmt: skip
    assert again.out == ""
    written = _rows((example / "out.csv").read_text())
    assert [float(r[0]) for r in written[1:]] == pytest.approx([k / 10 for k in range(21)])


def test_check_describes_the_system(example: Path) -> None:
    out = twinlink("cosim", "check", "msd.json", cwd=example).ok().out.splitlines()
    assert out[0] == "msd.json: a co-simulation (Maestro multi-model)"
    assert "  msd1.msd1i  MassSpringDamper1.fmu  (co-simulation, FMI 2.0)" in out
    assert "  msd2.msd2i.fk -> msd1.msd1i.fk" in out
    assert "algorithm: fixed-step 0.01 s, jacobi, from 0 s to 10 s" in out
    assert out[-1] == "algebraic loops: none"


def test_check_names_an_algebraic_loop_and_exits_1(example: Path) -> None:
    """The spring's force depends directly on its input x1 (its ModelStructure says so): fed
    back into x1, it is a loop no master can step."""
    (example / "loop.yaml").write_text(
        "instances: {s: MassSpringDamper2.fmu}\n"
        "connections: {s.fk: s.x1}\n"
        "algorithm: {type: fixed-step, size: 0.1}\n"
        "end_time: 1\n"
    )
    checked = twinlink("cosim", "check", "loop.yaml", cwd=example)
    assert checked.code == 1 and "Traceback" not in checked.err
    assert "algebraic loops (1):" in checked.out and "s.fk -> s.x1 -> s.fk" in checked.out
    ran = twinlink("cosim", "run", "loop.yaml", cwd=example)
    assert ran.code == 2 and "algebraic loop" in ran.err and "s.fk -> s.x1" in ran.err
    assert ran.out == "" and "Traceback" not in ran.err


def _mistake(example: Path, name: str, text: str) -> Done:
    (example / name).write_text(text)
    return twinlink("cosim", "run", name, cwd=example)


@pytest.mark.parametrize(
    ("name", "text", "says"),
    [
        ("nofmu.json", '{"fmus": {"{a}": "a.fmu"}, "connections": {"{a}.i.y": ["{b}.j.u"]}}',
         "nofmu.json: connections.{a}.i.y: the FMU {b} is not in fmus"),
        ("typo.yaml", "instances: {m: MassSpringDamper1.fmu}\nalgoritm: {size: 1}\n",
         "typo.yaml"),
        ("missing.json", '{"fmus": {"{a}": "gone.fmu"}, "logVariables": {"{a}.i": ["y"]}, '
         '"endTime": 1, "algorithm": {"type": "fixed-step", "size": 0.1}}',
         "instance 'a.i': its FMU gone.fmu is not there"),
        ("noend.json", '{"fmus": {"{m}": "MassSpringDamper1.fmu"}, '
         '"logVariables": {"{m}.i": ["x1"]}, "algorithm": {"type": "fixed-step", "size": 0.1}}',
         "has no end time: give one with --end"),
        ("notes.txt", "hello", "notes.txt: line 1, column 1: is not a mapping"),
    ],
)  # fmt: skip
def test_a_bad_file_is_one_line_and_exit_2(example: Path, name: str, text: str, says: str) -> None:
    done = _mistake(example, name, text)
    assert done.code == 2, done.err
    lines = done.err.strip().splitlines()
    assert len(lines) == 1 and says in lines[0] and name in lines[0], done.err
    assert done.out == ""


def test_a_failing_fmu_is_named_and_exit_1(example: Path) -> None:
    model = json.loads((EXAMPLE / "msd.json").read_text())
    model["parameters"]["{msd1}.msd1i.m1"] = 0.0  # the mass FMU refuses to step
    (example / "massless.json").write_text(json.dumps(model))
    done = twinlink("cosim", "run", "massless.json", cwd=example)
    assert done.code == 1 and "Traceback" not in done.err
    [line] = [x for x in done.err.splitlines() if x.startswith("Error:")]
    assert "instance 'msd1.msd1i'" in line and "the mass m1 must be positive" in line


def test_a_realtime_run_is_stopped_by_sigterm_with_its_rows(example: Path) -> None:
    """As a deployment stops its execute phase: SIGTERM ends the run after its current step,
    the CSV holds every row up to it, and the exit status is 0."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "twinlink", "cosim", "run", "msd.json", "--realtime", "1",
         "--end", "600", "-o", "paced.csv"],
        cwd=example, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        out = example / "paced.csv"
        # the CSV is written in blocks: once there is one, rows have been computed
        poll_until(lambda: out.exists() and out.stat().st_size > 0, "the first rows", 30)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "ended early (stopped at t = " in err and "Traceback" not in err
    rows = _rows((example / "paced.csv").read_text())
    assert rows[0] == HEADER and len(rows) >= 2
    last = float(rows[-1][0])
    assert f"(stopped at t = {last:g} s): {len(rows) - 1} rows to t = {last:g} s" in err
    assert last < 600


def test_a_realtime_run_says_how_late_its_steps_were(example: Path) -> None:
    done = twinlink("cosim", "run", "msd.json", "--realtime", "20", "--end", "1", cwd=example)
    assert len(_rows(done.ok().out)) == 1 + 101
    assert "finished: 101 rows to t = 1 s in " in done.err and "(lateness p50 " in done.err


def _history(server: Server, slug: str, stream: str = "cosim") -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    params: dict[str, Any] = {"limit": 100_000}
    with server.admin as admin:
        while True:
            r = admin.get(f"/api/v1/twins/{slug}/streams/{stream}/samples", params=params)
            assert r.status_code == 200, r.text
            page = r.json()
            rows += page["rows"]
            if not page.get("next_cursor"):
                return rows
            params["cursor"] = page["next_cursor"]


def test_the_rows_go_to_a_twin_as_a_devices_samples(example: Path, server: Server) -> None:
    slug, tokens = make_twin(server, devices=("sim",))
    before = time.time_ns()
    done = twinlink("cosim", "run", "msd.json", "-o", "sent.csv", "--prefix", "cs.", cwd=example,
                    TWINLINK_URL=server.url, TWINLINK_DEVICE_TOKEN=tokens["sim"]).ok()  # fmt: skip
    assert "sent 1001 samples in " in done.err
    csv_rows = _rows((example / "sent.csv").read_text())
    stored = _history(server, slug)
    assert len(stored) == 1001
    assert set(stored[0]["values"]) == {f"cs.{s}" for s in SIGNALS}
    # wall clock at the start plus the simulated time: 10 ms apart, from when it ran
    start = stored[0]["time"]
    assert before <= start <= time.time_ns()
    assert [r["time"] - start for r in stored[:3]] == [0, 10_000_000, 20_000_000]
    assert stored[-1]["time"] - start == 10_000_000_000
    for row, sample in zip(csv_rows[1:], stored, strict=True):
        assert [sample["values"][f"cs.{s}"] for s in SIGNALS] == [float(v) for v in row[1:]]


def test_a_wrong_device_token_fails_the_run_saying_so(example: Path, server: Server) -> None:
    done = twinlink("cosim", "run", "msd.json", "--device-token", "tld_not_a_token",
                    "--url", server.url, cwd=example)  # fmt: skip
    assert done.code == 1 and "Traceback" not in done.err
    assert "the samples were refused (HTTP 401)" in done.err and "--device-token" in done.err


def _admin(server: Server) -> dict[str, str]:
    return {"TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token}


def _view(example: Path, server: Server, cosim_id: str) -> dict[str, Any]:
    done = twinlink("cosim", "status", cosim_id, "--json", cwd=example, **_admin(server)).ok()
    view: dict[str, Any] = json.loads(done.out)
    return view


def test_the_server_runs_a_file_created_from_here(example: Path, server: Server) -> None:
    """`create` uploads the multi-model with the FMUs beside it (one tar), the server runs
    it, and its results are the rows the same file gives here."""
    slug, _ = make_twin(server, devices=())
    made = twinlink("cosim", "create", "msd.json", "--twin", slug, "--start", cwd=example,
                    **_admin(server)).ok().out  # fmt: skip
    cosim_id, rest = made.split(" ", 1)
    assert rest.startswith("msd: "), made
    view = poll_until(
        lambda: (
            (v := _view(example, server, cosim_id))["state"] not in ("created", "running") and v
        ),
        "the co-simulation to end",
        60,
    )
    assert view["state"] == "finished", view
    assert [i["name"] for i in view["system"]["instances"]] == ["msd1.msd1i", "msd2.msd2i"]
    status = twinlink("cosim", "status", cosim_id, cwd=example, **_admin(server)).ok().out
    assert status.strip().startswith(f"{cosim_id} msd: finished 100%"), status

    twinlink("cosim", "results", cosim_id, "-o", "server.csv", cwd=example,
             **_admin(server)).ok()  # fmt: skip
    here = _rows(twinlink("cosim", "run", "msd.json", cwd=example).ok().out)
    there = _rows((example / "server.csv").read_text())
    assert there[0] == here[0] == HEADER
    assert [[float(v) for v in r] for r in there[1:]] == [[float(v) for v in r] for r in here[1:]]
    assert len(_history(server, slug)) == 1001  # and into the twin's history

    listed = twinlink("cosim", "list", cwd=example, **_admin(server)).ok().out.splitlines()
    assert listed[0].split()[:3] == ["ID", "NAME", "STATE"]
    assert [cosim_id, "msd", "finished"] in [line.split()[:3] for line in listed[1:]]
    assert twinlink("cosim", "rm", cosim_id, cwd=example, **_admin(server)).ok().out.strip() == (
        f"{cosim_id}: deleted"
    )
    gone = twinlink("cosim", "status", cosim_id, cwd=example, **_admin(server))
    assert gone.code == 1 and "(404)" in gone.err and "Traceback" not in gone.err


def test_a_realtime_cosim_on_the_server_is_stopped_from_here(example: Path, server: Server) -> None:
    model = json.loads((EXAMPLE / "msd.json").read_text())
    model["endTime"] = 3600.0
    (example / "long.json").write_text(json.dumps(model))
    made = twinlink("cosim", "create", "long.json", "--mode", "realtime", "--factor", "1",
                    cwd=example, **_admin(server)).ok().out  # fmt: skip
    cosim_id = made.split(" ", 1)[0]
    assert made.strip().endswith("long: created"), made
    started = twinlink("cosim", "start", cosim_id, cwd=example, **_admin(server)).ok().out
    assert f"{cosim_id} long: running" in started
    poll_until(lambda: (_view(example, server, cosim_id).get("sim_time") or 0) > 0,
               "the run to get going", 60)  # fmt: skip
    stopped = twinlink("cosim", "stop", cosim_id, cwd=example, **_admin(server)).ok().out
    assert stopped.startswith(f"{cosim_id} long: "), stopped
    view = poll_until(
        lambda: (v := _view(example, server, cosim_id))["state"] != "running" and v,
        "the stop",
        60,
    )
    assert view["state"] == "stopped", view
    rows = _rows(twinlink("cosim", "results", cosim_id, cwd=example, **_admin(server)).ok().out)
    assert rows[0] == HEADER and 1 < len(rows) < 360_001


def test_create_refuses_what_is_not_a_cosimulation(example: Path, server: Server) -> None:
    (example / "notes.txt").write_text("hello")
    done = twinlink("cosim", "create", "notes.txt", cwd=example, **_admin(server))
    assert done.code == 2 and "give a .json, .yaml, .ssp" in done.err
    (example / "noalgorithm.json").write_text('{"fmus": {"{a}": "a.fmu"}}')
    unread = twinlink("cosim", "create", "noalgorithm.json", cwd=example, **_admin(server))
    assert unread.code == 2 and "noalgorithm.json: algorithm: missing" in unread.err
    # read here, but its FMU is nowhere: the server says so
    (example / "nofmus.json").write_text(
        '{"fmus": {"{a}": "a.fmu"}, "logVariables": {"{a}.i": ["y"]}, "endTime": 1, '
        '"algorithm": {"type": "fixed-step", "size": 0.1}}'
    )
    refused = twinlink("cosim", "create", "nofmus.json", cwd=example, **_admin(server))
    assert refused.code == 1 and "(422)" in refused.err and "a.fmu" in refused.err, refused.err
    assert "Traceback" not in refused.err + unread.err


class _Ingest(BaseHTTPRequestHandler):
    """HTTP ingest as a flaky server answers it: the first batch 503, then acks."""

    bodies: ClassVar[list[dict[str, Any]]] = []

    def do_POST(self) -> None:
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        type(self).bodies.append(body)
        if len(self.bodies) == 1:
            self.send_response(503)
            answer = {"detail": "the store is busy; send it again"}
        else:
            self.send_response(200)
            answer = {"type": "ack", "seq": body["seq"], "accepted": len(body["samples"]),
                      "rejected": [], "rejected_count": 0}  # fmt: skip
        data = json.dumps(answer).encode()
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def log_message(self, *args: Any) -> None:
        pass


def test_a_batch_is_sent_again_with_its_seq_and_nan_is_left_out() -> None:
    """A 503 is transient: the same batch (same seq) again, so the platform stores it once.
    JSON has no NaN: a value that is not finite is left out of its sample, and a sample with
    none left is not sent."""
    _Ingest.bodies = []
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), _Ingest)
    serving = threading.Thread(target=httpd.serve_forever, daemon=True)
    serving.start()
    try:
        url = f"http://127.0.0.1:{httpd.server_address[1]}"
        sender = DeviceSender(url, "tld_x", ["a.x", "b.y"], t0=1.0, start_ns=5_000_000_000)
        for row in ([1.0, 0.5, 2.0], [1.5, math.nan, 3.0], [2.0, math.inf, math.nan]):
            sender.add(np.array(row))
        sent = sender.close()
    finally:
        httpd.shutdown()
        httpd.server_close()
    first, second = _Ingest.bodies
    assert first == second and first["stream"] == "cosim" and first["time_unit"] == "ns"
    assert first["samples"] == [
        {"time": 5_000_000_000, "values": {"a.x": 0.5, "b.y": 2.0}},
        {"time": 5_500_000_000, "values": {"b.y": 3.0}},
    ]
    assert (sent.accepted, sent.batches, sent.rejected) == (2, 1, 0)


def test_an_ssp_archive_runs_recording_every_output(example: Path) -> None:
    """SSP names no variables to record and has no step: every output is recorded, and
    --step gives the step."""
    archive = example / "msd.ssp"
    ssp = ROOT / "tests" / "cosim_files" / "msd_ssp"
    with zipfile.ZipFile(archive, "w") as z:
        z.write(ssp / "SystemStructure.ssd", "SystemStructure.ssd")
        z.write(ssp / "resources" / "msd2.ssv", "resources/msd2.ssv")
        for fmu in ("MassSpringDamper1.fmu", "MassSpringDamper2.fmu"):
            z.write(example / fmu, f"resources/{fmu}")
    checked = twinlink("cosim", "check", "msd.ssp", cwd=example).ok().out.splitlines()
    assert checked[0] == "msd.ssp: a co-simulation (SSP archive)"
    assert f"recorded (5, every output: the file names none): {', '.join(SIGNALS)}" in checked
    rows = _rows(twinlink("cosim", "run", "msd.ssp", "--step", "0.01", cwd=example).ok().out)
    assert rows[0] == ["time", *SIGNALS] and len(rows) == 1 + 1001
