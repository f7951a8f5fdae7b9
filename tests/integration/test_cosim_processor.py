"""The `cosim` processor: a co-simulation of several FMUs beside live data (mode 3).

The mass-spring-damper pair (tests/fmus/msd_mass, msd_spring) runs coupled as one batch
co-simulation first (Jacobi, 10 ms steps); its mass's position and velocity are then streamed
by a device, as if measured, into the spring instance of a processor running the pair with
that connection cut (the spring's x1 and v1 fed by the signals, the force still feeding the
mass). Jacobi steps the spring from the mass's values at the step's start, which are the
samples, so the processor's outputs are the batch run's values, in the twin's history at the
samples' times. Bad ports are a 422 at create; a stop, a restart or a killed worker leaves
no instance and no extracted FMU behind (a worker extracts them in its processor's workdir,
found from the FMU binaries it has loaded).
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from signal import SIGKILL
from typing import Any

import numpy as np
import pytest

from tests.conftest import FmuFiles, Server, stop_server
from tests.integration._fmu_types import build_echo_fmu
from tests.integration._live import TIMEOUT_S, device_twin
from tests.integration._processors import (
    T0,
    events,
    processor_server,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._util import assert_problem
from tests.integration.test_fmu_processors import upload
from twinlink.cosim.runner import run
from twinlink.cosim.yamlform import from_mapping

pytestmark = pytest.mark.integration

STEP_S = 0.01
STEP_NS = 10_000_000
FMUS = {"Mass.fmu": "msd_mass", "Spring.fmu": "msd_spring"}
COUPLED: dict[str, Any] = {
    "instances": {"m1": "Mass.fmu", "s2": "Spring.fmu"},
    "connections": {"m1.x1": "s2.x1", "m1.v1": "s2.v1", "s2.fk": "m1.fk"},
    "parameters": {"s2.c2": 2.0, "s2.cc": 3.0},
    "log": {"m1": ["x1", "v1"], "s2": ["x2", "fk"]},
    "algorithm": {"type": "fixed-step", "size": STEP_S, "master": "jacobi"},
    "end_time": 2.0,
}
# The same pair with the mass's position and velocity fed to the spring from live data.
BESIDE = {**COUPLED, "connections": {"s2.fk": "m1.fk"}, "log": {}}
BESIDE.pop("end_time")
INPUTS = {"x1": "s2.x1", "v1": "s2.v1"}
OUTPUTS = {"x2": "s2.x2", "force": "s2.fk", "x1_model": "m1.x1"}


@pytest.fixture(scope="module")
def tmpdir_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Server, Path]]:
    """A server whose workers' TMPDIR is a folder of this module (where nothing should go)."""
    scratch = tmp_path_factory.mktemp("scratch")
    srv = processor_server(tmp_path_factory.mktemp("data"), TMPDIR=str(scratch))
    try:
        yield srv, scratch
    finally:
        stop_server(srv)


@pytest.fixture(scope="module")
def reference(fmu_files: FmuFiles) -> dict[str, np.ndarray]:
    """The coupled pair run as one batch co-simulation: its columns by name."""
    paths = {name: fmu_files(build) for name, build in FMUS.items()}
    result = run(from_mapping(COUPLED), paths)
    assert not result.ended
    return {name: result.column(name) for name in result.columns}


def twin_with_fmus(server: Server, fmu_files: FmuFiles) -> tuple[str, str]:
    slug, [device] = device_twin(server)
    for name, build in FMUS.items():
        upload(server, slug, fmu_files(build), name)
    return slug, device


def create(server: Server, slug: str, body: dict[str, Any]) -> Any:
    with server.admin as admin:
        return admin.post(f"/api/v1/twins/{slug}/processors", json=body)


def cosim(name: str, system: dict[str, Any], **params: Any) -> dict[str, Any]:
    params = {"inputs": INPUTS, "outputs": OUTPUTS, **params}
    return {"name": name, "blueprint": "cosim", "params": {"system": system, **params}}


def post_measured(server: Server, device: str, ref: dict[str, np.ndarray], t0: int) -> None:
    """The mass's position and velocity of the batch run, one sample per step, in a few
    requests (so a batch ends between grid points as well as on one)."""
    n = len(ref["time"])
    for seq, start in enumerate(range(0, n, 57), start=1):
        rows = [
            {"time": t0 + k * STEP_NS, "values": {"x1": ref["m1.x1"][k], "v1": ref["m1.v1"][k]}}
            for k in range(start, min(n, start + 57))
        ]
        with server.client(device) as c:
            r = c.post("/api/v1/device/samples", json={"seq": t0 // STEP_NS + seq, "samples": rows})
        assert r.status_code == 200 and r.json()["accepted"] == len(rows), r.text


def history(server: Server, slug: str, stream: str) -> list[dict[str, Any]]:
    with server.admin as admin:
        r = admin.get(
            f"/api/v1/twins/{slug}/streams/{stream}/samples",
            params={"start": "1970-01-01T00:00:00Z", "limit": 100_000},
        )
    if r.status_code == 404:  # nothing stored yet
        return []
    assert r.status_code == 200, r.text
    return r.json()["rows"]  # type: ignore[no-any-return]


def poll(what: Callable[[], Any], done: Callable[[Any], bool]) -> Any:
    """`what()` once `done` holds for it (fails after TIMEOUT_S)."""
    deadline = time.monotonic() + TIMEOUT_S
    while True:
        value = what()
        if done(value):
            return value
        assert time.monotonic() < deadline, f"never reached: {value!r}"[:2000]
        time.sleep(0.05)


def session_dir(server: Server, pid: int) -> Path:
    """The folder worker `pid` extracted its FMUs into (it has their binaries loaded): in its
    processor's workdir, which each start of a worker empties."""
    for line in Path(f"/proc/{pid}/maps").read_text().splitlines():
        fields = line.split(maxsplit=5)
        if len(fields) == 6 and "/twinlink-cosim-" in fields[5]:
            path = Path(fields[5])
            folder = next(p for p in path.parents if p.name.startswith("twinlink-cosim-"))
            assert folder.parent.parent == server.data_dir.resolve() / "processors", folder
            return folder
    raise AssertionError(f"worker {pid} has no FMU of a co-simulation loaded")


def left_in(folder: Path) -> list[Path]:
    """The extracted co-simulations in the workdir that holds `folder`."""
    return sorted(folder.parent.glob("twinlink-cosim-*"))


def check_outputs(got: list[dict[str, Any]], ref: dict[str, np.ndarray], t0: int) -> None:
    """One output per communication point at the sample's time, the batch run's values."""
    n = len(ref["time"])
    assert [s["time"] for s in got] == [t0 + k * STEP_NS for k in range(n)]
    for signal, column in (("x2", "s2.x2"), ("force", "s2.fk"), ("x1_model", "m1.x1")):
        values = np.array([s["values"][signal] for s in got])
        np.testing.assert_allclose(values, ref[column], rtol=0, atol=1e-12, err_msg=signal)
    assert np.ptp(ref["s2.x2"]) > 0.1  # the spring's mass moves: the values say something


def test_a_device_streams_into_the_co_simulation_and_its_outputs_go_to_history(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, reference: dict[str, np.ndarray]
) -> None:
    server, scratch = tmpdir_server
    slug, device = twin_with_fmus(server, fmu_files)
    r = create(server, slug, cosim("pair", BESIDE))
    assert r.status_code == 201, r.text
    view = wait_for(server, slug, "pair", lambda p: p["state"] == "running")
    folder = session_dir(server, view["pid"])
    assert left_in(folder) == [folder] and list(scratch.glob("twinlink-cosim-*")) == []
    n = len(reference["time"])
    with watching(server, slug, "pair") as ws:
        post_measured(server, device, reference, T0)
        got = samples_until(ws, lambda s: len(s) >= n)
    check_outputs(got, reference, T0)
    stored = poll(lambda: history(server, slug, "pair"), lambda rows: len(rows) >= n)
    check_outputs(stored, reference, T0)
    view = wait_for(server, slug, "pair", lambda p: p["stats"]["samples_out"] >= n)
    assert view["stats"]["crashes"] == 0 and view["last_error"] is None
    # Stopped: the worker ends, freeing the instances and removing what it extracted.
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/pair/stop")
    assert r.status_code == 200, r.text
    wait_for(server, slug, "pair", lambda p: p["state"] == "stopped" and p["pid"] is None)
    assert left_in(folder) == []


def test_a_restart_starts_the_co_simulation_again_at_the_next_sample(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, reference: dict[str, np.ndarray]
) -> None:
    server, _ = tmpdir_server
    slug, device = twin_with_fmus(server, fmu_files)
    assert create(server, slug, cosim("again", BESIDE)).status_code == 201
    first = wait_for(server, slug, "again", lambda p: p["state"] == "running")
    old = session_dir(server, first["pid"])
    n = len(reference["time"])
    with watching(server, slug, "again") as ws:
        post_measured(server, device, reference, T0)
        samples_until(ws, lambda s: len(s) >= n)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/again/restart")
    assert r.status_code == 200, r.text
    view = wait_for(
        server, slug, "again", lambda p: p["state"] == "running" and p["pid"] != first["pid"]
    )
    folder = session_dir(server, view["pid"])
    assert folder != old and left_in(folder) == [folder]  # the old worker's is gone
    # Time 0 again at the first new sample: the same outputs, from there on.
    t1 = T0 + 3600 * 10**9
    with watching(server, slug, "again") as ws:
        post_measured(server, device, reference, t1)
        got = samples_until(ws, lambda s: len(s) >= n)
    check_outputs(got, reference, t1)
    with server.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}/processors/again").status_code == 204
    poll(lambda: left_in(folder), lambda found: found == [])


def test_the_end_time_finishes_the_processor(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, reference: dict[str, np.ndarray]
) -> None:
    server, _ = tmpdir_server
    slug, device = twin_with_fmus(server, fmu_files)
    assert create(server, slug, cosim("short", {**BESIDE, "end_time": 0.5})).status_code == 201
    view = wait_for(server, slug, "short", lambda p: p["state"] == "running")
    folder = session_dir(server, view["pid"])
    with watching(server, slug, "short") as ws:
        post_measured(server, device, reference, T0)
        got = samples_until(ws, lambda s: len(s) >= 51)
    cut = {name: column[:51] for name, column in reference.items()}  # 0 to 0.5 s
    check_outputs(got, cut, T0)
    view = wait_for(server, slug, "short", lambda p: p["state"] == "finished")
    assert view["pid"] is None and view["stats"]["restarts"] == 0
    assert view["stats"]["samples_out"] == 51
    [event] = events(server, slug, "short", "finished")
    assert "reached its end time t = 0.5 s" in event["message"]
    assert events(server, slug, "short", "failed") == []
    assert left_in(folder) == []


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"inputs": {"x1": "s3.x1"}}, "inputs.x1: 's3.x1' is not instance.variable"),
        ({"inputs": {"x1": "m1.fk"}}, "inputs: x1 (m1.fk): a connection of the system feeds"),
        ({"inputs": {"x1": "s2.x1", "x": "s2.x1"}}, "s2.x1 is fed by two signals"),
        ({"outputs": {"x2": "spring.x2"}}, "outputs.x2: 'spring.x2' is not instance.variable"),
        ({"outputs": {}}, "outputs: Value error, name at least one output"),
        ({"outputs": {"bad name": "s2.x2"}}, "'bad name' is not a signal name"),
        ({"system": {**BESIDE, "algorithm": {"type": "fast", "size": 0.1}}}, "algorithm.type"),
        ({"system": {**BESIDE, "colour": 1}}, "system: colour: unknown key"),
        ({"system": {**BESIDE, "connections": {"s2.fk": "m9.fk"}}}, "'m9.fk' is not instance"),
        ({"system": {**BESIDE, "instances": {"m1": "lib:msd/Mass", "s2": "Spring.fmu"}}},
         "instances.m1: library FMUs (lib:msd/Mass) are not supported"),
        ({"system": {**BESIDE, "instances": {"m1": "../Mass.fmu", "s2": "Spring.fmu"}}},
         "instances.m1: '../Mass.fmu' is not the file name of an FMU"),
    ],
)  # fmt: skip
def test_bad_ports_and_systems_are_refused_at_create_naming_the_key(
    tmpdir_server: tuple[Server, Path], change: dict[str, Any], named: str
) -> None:
    server, _ = tmpdir_server
    slug, _ = device_twin(server)
    body = cosim("bad", BESIDE)
    body["params"] |= change
    problem = assert_problem(create(server, slug, body), 422)
    assert named in problem["detail"], problem["detail"]
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/processors")
    assert r.json()["processors"] == [], r.text  # nothing was made


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"outputs": {"x2": "s2.x9"}}, "outputs.x2 (s2.x9): Spring.fmu has no variable 'x9'"),
        ({"inputs": {"x1": "m1.x0"}}, "params: inputs.x1 (m1.x0): Mass.fmu has no variable 'x0'"),
        ({"system": {**BESIDE, "parameters": {"s2.c9": 1.0}}},
         "params: system: parameters.s2.c9: Spring.fmu has no variable 'c9'"),
        ({"system": {**BESIDE, "instances": {"m1": "Mass.fmu", "s2": "Other.fmu"}}},
         "params: twin '{slug}' has no FMU 'Other.fmu'; upload it first"),
    ],
)  # fmt: skip
def test_a_variable_or_an_fmu_the_twin_lacks_is_refused_at_create(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, change: dict[str, Any], named: str
) -> None:
    server, _ = tmpdir_server
    slug, _ = twin_with_fmus(server, fmu_files)
    body = cosim("typo", BESIDE)
    body["params"] |= change
    problem = assert_problem(create(server, slug, body), 422)
    assert named.format(slug=slug) in problem["detail"], problem["detail"]


def test_an_fmu_in_use_is_not_deleted_and_one_replaced_under_it_fails_its_start(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles
) -> None:
    """Its FMUs cannot be deleted while the processor exists (409); one replaced by an
    upload without a variable it uses fails the next start of its worker, saying why, and a
    start through the API is then a 422. Stopping it is never refused."""
    server, _ = tmpdir_server
    slug, _ = twin_with_fmus(server, fmu_files)
    assert create(server, slug, cosim("swap", BESIDE)).status_code == 201
    first = wait_for(server, slug, "swap", lambda p: p["state"] == "running")
    folder = session_dir(server, first["pid"])
    with server.admin as admin:
        problem = assert_problem(admin.delete(f"/api/v1/twins/{slug}/fmus/Spring.fmu"), 409)
    assert "used by processor(s) swap" in problem["detail"]
    upload(server, slug, fmu_files("msd_mass"), "Spring.fmu")  # its x1 is an output
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/swap/restart")
    assert r.status_code == 200, r.text
    view = wait_for(server, slug, "swap", lambda p: p["last_error"] is not None)
    assert (
        "the co-simulation cannot start: instance 's2' (Spring.fmu): x1 is an output"
        in (view["last_error"])
    )
    assert view["pid"] != first["pid"]
    with server.admin as admin:
        assert admin.post(f"/api/v1/twins/{slug}/processors/swap/stop").status_code == 200
        problem = assert_problem(admin.post(f"/api/v1/twins/{slug}/processors/swap/start"), 422)
    assert "Spring.fmu has no variable" in problem["detail"], problem["detail"]
    wait_for(server, slug, "swap", lambda p: p["state"] == "stopped" and p["pid"] is None)
    assert left_in(folder) == []


@pytest.mark.parametrize("version", ["stair", "stair3"])
def test_an_fmu_that_ends_the_simulation_finishes_the_processor(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, version: str
) -> None:
    """The Stair FMU (tests/fmus/stair) counts 1 + floor(t) and ends the simulation at 9 s:
    the rows up to its end are written, the last at 9 s, and the processor is finished."""
    server, _ = tmpdir_server
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files(version), "Stair.fmu")
    system = {"instances": {"st": "Stair.fmu"}, "algorithm": {"type": "fixed-step", "size": 0.4}}
    body = {"name": "stair", "blueprint": "cosim",
            "params": {"system": system, "outputs": {"counter": "st.counter"}}}  # fmt: skip
    assert create(server, slug, body).status_code == 201
    view = wait_for(server, slug, "stair", lambda p: p["state"] == "running")
    folder = session_dir(server, view["pid"])
    rows = [{"time": T0 + k * 700_000_000, "values": {"x": float(k)}} for k in range(20)]
    with watching(server, slug, "stair") as ws:
        with server.client(device) as c:
            r = c.post("/api/v1/device/samples", json={"seq": 1, "samples": rows})
        assert r.status_code == 200, r.text
        got = samples_until(ws, lambda s: len(s) >= 24)
    t_s = [n * 0.4 for n in range(23)] + [9.0]  # 0 to 8.8 s, then the step to 9.2 ends at 9
    assert [s["time"] for s in got] == [T0 + round(t * 1e9) for t in t_s]
    assert [s["values"]["counter"] for s in got] == [1.0 + math.floor(t + 1e-9) for t in t_s]
    view = wait_for(server, slug, "stair", lambda p: p["state"] == "finished")
    assert view["stats"]["samples_out"] == 24 and view["stats"]["restarts"] == 0
    assert view["stats"]["crashes"] == 0 and view["last_error"] is None
    [event] = events(server, slug, "stair", "finished")
    assert event["message"].startswith("the co-simulation ended: "), event
    assert "t = 9 s" in event["message"] and event["data"]["sim_time_s"] == 9.0
    assert left_in(folder) == []


def test_a_killed_worker_leaves_nothing_behind_once_restarted(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, reference: dict[str, np.ndarray]
) -> None:
    """A worker killed outright (SIGKILL: no stop runs) leaves its extracted FMUs; the next
    worker empties the workdir before it opens the co-simulation again."""
    server, _ = tmpdir_server
    slug, device = twin_with_fmus(server, fmu_files)
    assert create(server, slug, cosim("killed", BESIDE)).status_code == 201
    first = wait_for(server, slug, "killed", lambda p: p["state"] == "running")
    old = session_dir(server, first["pid"])
    os.kill(first["pid"], SIGKILL)
    view = wait_for(
        server, slug, "killed", lambda p: p["state"] == "running" and p["pid"] != first["pid"]
    )
    assert view["stats"]["crashes"] == 1
    folder = session_dir(server, view["pid"])
    assert left_in(folder) == [folder] and not old.exists()
    with watching(server, slug, "killed") as ws:  # and it runs from time 0 again
        post_measured(server, device, reference, T0)
        got = samples_until(ws, lambda s: len(s) >= len(reference["time"]))
    check_outputs(got, reference, T0)
    with server.admin as admin:
        assert admin.post(f"/api/v1/twins/{slug}/processors/killed/stop").status_code == 200
    wait_for(server, slug, "killed", lambda p: p["state"] == "stopped")
    assert left_in(folder) == []


def test_a_var_step_co_simulation_steps_up_to_each_batch_and_follows_the_data(
    tmpdir_server: tuple[Server, Path], fmu_files: FmuFiles, reference: dict[str, np.ndarray]
) -> None:
    """Var-step chooses its own steps: they start before the batch's last sample, the last
    may end after it; the outputs follow the coupled run's to within the held inputs' error."""
    server, _ = tmpdir_server
    slug, device = twin_with_fmus(server, fmu_files)
    algorithm = {"type": "var-step", "size": 0.005, "min_size": 0.001, "max_size": 0.05}
    assert create(server, slug, cosim("var", {**BESIDE, "algorithm": algorithm})).status_code == 201
    wait_for(server, slug, "var", lambda p: p["state"] == "running")
    last_s = reference["time"][-1]
    with watching(server, slug, "var") as ws:
        post_measured(server, device, reference, T0)
        got = samples_until(ws, lambda s: bool(s) and s[-1]["time"] >= T0 + round(last_s * 1e9))
    t = np.array([(s["time"] - T0) * 1e-9 for s in got])
    assert t[0] == 0.0 and bool(np.all(np.diff(t) > 0))
    assert last_s <= t[-1] < last_s + 0.05  # the last step began before the last sample
    x2 = np.array([s["values"]["x2"] for s in got])
    assert np.max(np.abs(x2 - np.interp(t, reference["time"], reference["s2.x2"]))) < 0.02
    view = wait_for(server, slug, "var", lambda p: p["stats"]["samples_out"] == len(got))
    assert view["state"] == "running" and view["last_error"] is None


# (FMI version, the echo FMU's inputs used, the samples, the values that reach the FMU, the
# inputs some sample has out of range: samples 1 and 2, skipped with out_of_range "reject")
ECHO_CASES = [
    (2, ["x", "n", "b"],
     [[0.5, 2.6, 0.2], [1.5, 9.0, 0.0], [2.5, -7.0, 1.0], [3.5, 1.0, 0.0], [4.5, 0.0, 1.0]],
     [[0.5, 3, 1], [1.5, 5, 0], [2.5, -5, 1], [3.5, 1, 0], [4.5, 0, 1]],
     {"n"}),
    (3, ["f32", "u8", "i32"],
     [[0.25, 3.0, 2.6], [-1.5, 300.0, 9.0], [2.0, -4.0, -7.0], [3.0, 7.4, 0.0], [0.0, 0.0, 0.0]],
     [[0.25, 3, 3], [-1.5, 255, 5], [2.0, 0, -5], [3.0, 7, 0], [0.0, 0, 0]],
     {"u8", "i32"}),
]  # fmt: skip


@pytest.mark.parametrize("mode", ["clamp", "reject"])
@pytest.mark.parametrize(("version", "names", "samples", "came", "out"), ECHO_CASES)
def test_typed_inputs_are_rounded_and_kept_in_range_as_in_the_fmu_processor(
    tmpdir_server: tuple[Server, Path],
    tmp_path: Path,
    version: int,
    names: list[str],
    samples: list[list[float]],
    came: list[list[float]],
    out: set[str],
    mode: str,
) -> None:
    """The echo FMU (tests/integration/_fmu_types.py) outputs its inputs as they were set:
    integers rounded, Booleans nonzero, values outside the declared or type's range clamped
    (or the sample skipped), as the FMU processor's out_of_range. The step from t_k uses the
    samples up to t_k, so the row at t_k+1 echoes them (the first row, after
    initialization, sample 0)."""
    server, _ = tmpdir_server
    slug, [device] = device_twin(server)
    fmu = f"echo{'' if version == 2 else '3'}.fmu"
    upload(server, slug, build_echo_fmu(tmp_path, version), fmu)
    system = {"instances": {"echo": fmu}, "algorithm": {"type": "fixed-step", "size": 0.1}}
    params = {"system": system, "out_of_range": mode,
              "inputs": {f"s_{n}": f"echo.{n}" for n in names},
              "outputs": {n: f"echo.{n}_out" for n in names}}  # fmt: skip
    r = create(server, slug, {"name": "echo", "blueprint": "cosim", "params": params})
    assert r.status_code == 201, r.text
    wait_for(server, slug, "echo", lambda p: p["state"] == "running")
    rows = [
        {
            "time": T0 + k * 100_000_000,
            "values": {f"s_{n}": v for n, v in zip(names, row, strict=True)},
        }
        for k, row in enumerate(samples)
    ]
    with watching(server, slug, "echo") as ws:
        with server.client(device) as c:
            r = c.post("/api/v1/device/samples", json={"seq": 1, "samples": rows})
        assert r.status_code == 200, r.text
        got = samples_until(ws, lambda s: len(s) >= len(samples))
    kept = [0, 3, 4] if mode == "reject" else range(len(samples))
    held = [max(k for k in kept if k <= max(0, j - 1)) for j in range(len(samples))]
    assert [s["time"] for s in got] == [T0 + k * 100_000_000 for k in range(len(samples))]
    assert [[s["values"][n] for n in names] for s in got] == [came[k] for k in held]
    kind = "input_clamped" if mode == "clamp" else "input_rejected"
    reported = {e["data"]["input"] for e in events(server, slug, "echo", kind)}
    assert reported == {f"echo.{n}" for n in out}
