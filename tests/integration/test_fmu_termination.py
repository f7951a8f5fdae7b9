"""An FMU that ends its own simulation finishes its processor; it does not crash it.

The Stair test FMUs (tests/fmus/stair, FMI 2.0 and 3.0) count 1 + floor(t) and end the
simulation at t = 9 s: FMI 2 with fmi2Discard and fmi2Terminated, FMI 3 with
terminateRequested (and an early return when the step was meant to go further). The outputs up
to and including the terminating step are written, the last at t = 9 s; the processor is
`finished` with an event, no restart, no crash, no new worker; it stays finished after more
samples and across a server restart, until it is restarted through the API (from t = 0).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FmuFiles, Server, restart_server, stop_server
from tests.integration._live import device_twin
from tests.integration._processors import (
    BLUEPRINTS,
    T0,
    create,
    events,
    processor,
    processor_server,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration.test_fmu_processors import upload

pytestmark = pytest.mark.integration

SPACING_NS = 700_000_000  # 0.7 s: no sample falls on t = 9 s, where the FMU ends
N_SAMPLES = 20  # up to t = 13.3 s
# 0, 0.7, ..., 8.4 s (13 samples), then the terminating step's row at 9 s
EXPECTED_T_S = [k * 0.7 for k in range(13)] + [9.0]
EXPECTED_COUNTER = [1.0 + math.floor(t + 1e-9) for t in EXPECTED_T_S]


def post_at(server: Server, device: str, seq: int, ks: range, t0: int = T0) -> None:
    """Samples k of `ks` at t0 + k * 0.7 s, in one request."""
    rows = [{"time": t0 + k * SPACING_NS, "values": {"x": float(k)}} for k in ks]
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": rows})
    assert r.status_code == 200 and r.json()["accepted"] == len(rows), r.text


def post_all(server: Server, device: str, batches: str, t0: int = T0, seq: int = 1) -> int:
    """All N_SAMPLES samples in one request, or each in its own; the next seq."""
    if batches == "one":
        post_at(server, device, seq, range(N_SAMPLES), t0)
        return seq + 1
    for k in range(N_SAMPLES):
        post_at(server, device, seq + k, range(k, k + 1), t0)
    return seq + N_SAMPLES


def stair(server: Server, fmu_files: FmuFiles, version: str) -> tuple[str, str]:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files(version), "Stair.fmu")
    create(server, slug, name="stair", blueprint="fmu",
           params={"fmu": "Stair.fmu", "outputs": ["counter"]})  # fmt: skip
    return slug, device


def check_finished(server: Server, slug: str, got: list[dict[str, Any]], t0: int = T0) -> None:
    assert [s["values"]["counter"] for s in got] == EXPECTED_COUNTER
    assert [s["time"] for s in got] == [t0 + round(t * 1e9) for t in EXPECTED_T_S]
    view = wait_for(server, slug, "stair", lambda p: p["state"] == "finished")
    assert view["pid"] is None and view["last_error"] is None
    assert view["stats"]["restarts"] == 0 and view["stats"]["crashes"] == 0
    assert view["stats"]["samples_out"] == len(EXPECTED_T_S)
    [event] = events(server, slug, "stair", "finished")
    assert "terminate at t = 9 s" in event["message"] and event["data"]["fmu_time_s"] == 9.0
    assert events(server, slug, "stair", "failed") == []
    assert events(server, slug, "stair", "crashed") == []


@pytest.mark.parametrize("version", ["stair", "stair3"])
@pytest.mark.parametrize("batches", ["one", "many"])
def test_an_fmu_that_terminates_finishes_its_processor(
    server: Server, fmu_files: FmuFiles, version: str, batches: str
) -> None:
    slug, device = stair(server, fmu_files, version)
    wait_for(server, slug, "stair", lambda p: p["state"] == "running")
    with watching(server, slug, "stair") as ws:
        seq = post_all(server, device, batches)
        got = samples_until(ws, lambda s: len(s) >= len(EXPECTED_T_S))
    check_finished(server, slug, got)
    [started] = events(server, slug, "stair", "started")  # no new worker
    # More samples: it stays finished, they are dropped, no worker starts.
    post_all(server, device, batches, T0 + 100 * SPACING_NS, seq)
    view = wait_for(server, slug, "stair", lambda p: p["stats"]["dropped"] >= N_SAMPLES)
    assert view["state"] == "finished" and view["stats"]["samples_out"] == len(EXPECTED_T_S)
    assert events(server, slug, "stair", "started") == [started]


def test_a_finished_processor_stays_finished_across_a_restart_until_restarted(
    tmp_path: Path, fmu_files: FmuFiles
) -> None:
    srv = processor_server(tmp_path)
    try:
        slug, device = stair(srv, fmu_files, "stair")
        wait_for(srv, slug, "stair", lambda p: p["state"] == "running")
        with watching(srv, slug, "stair") as ws:
            post_all(srv, device, "one")
            got = samples_until(ws, lambda s: len(s) >= len(EXPECTED_T_S))
        check_finished(srv, slug, got)
    finally:
        stop_server(srv)
    srv = restart_server(srv, {"TWINLINK_BLUEPRINTS_DIR": str(BLUEPRINTS)})
    try:
        view = processor(srv, slug, "stair")
        assert view["state"] == "finished" and view["pid"] is None
        assert len(events(srv, slug, "stair", "started")) == 1  # not started again
        with srv.admin as admin:
            r = admin.post(f"/api/v1/twins/{slug}/processors/stair/restart")
        assert r.status_code == 200, r.text
        wait_for(srv, slug, "stair", lambda p: p["state"] == "running")
        # Started again from t = 0: the same outputs, from the first new sample on.
        t0 = T0 + 1000 * SPACING_NS
        with watching(srv, slug, "stair") as ws:
            post_all(srv, device, "one", t0, seq=100)
            got = samples_until(ws, lambda s: len(s) >= len(EXPECTED_T_S))
        assert [s["values"]["counter"] for s in got] == EXPECTED_COUNTER
        wait_for(srv, slug, "stair", lambda p: p["state"] == "finished")
        assert len(events(srv, slug, "stair", "finished")) == 2
    finally:
        stop_server(srv)


@pytest.mark.parametrize("version", ["stair", "stair3"])
def test_on_a_fixed_step_grid_the_steps_up_to_the_end_are_written(
    server: Server, fmu_files: FmuFiles, version: str
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files(version), "Stair.fmu")
    create(server, slug, name="stair", blueprint="fmu",
           params={"fmu": "Stair.fmu", "outputs": ["counter"], "step": "fixed",
                   "step_size_s": 0.4})  # fmt: skip
    wait_for(server, slug, "stair", lambda p: p["state"] == "running")
    with watching(server, slug, "stair") as ws:
        post_all(server, device, "one")  # up to 13.3 s
        got = samples_until(ws, lambda s: len(s) >= 23)
    # steps of 0.4 s to 8.8 s (22 steps), then the step to 9.2 s ends at 9 s
    t_s = [n * 0.4 for n in range(1, 23)] + [9.0]
    assert [s["time"] for s in got] == [T0 + round(t * 1e9) for t in t_s]
    assert [s["values"]["counter"] for s in got] == [1.0 + math.floor(t + 1e-9) for t in t_s]
    view = wait_for(server, slug, "stair", lambda p: p["state"] == "finished")
    assert view["stats"]["samples_out"] == 23 and view["stats"]["restarts"] == 0
