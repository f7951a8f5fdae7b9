"""Processors end to end: a real server, worker processes, the bus, history and live views."""

from __future__ import annotations

from pathlib import Path

import psutil
import pytest

from tests.conftest import Server, restart_server, stop_server
from tests.integration._live import device_twin
from tests.integration._processors import (
    BLUEPRINTS,
    MS,
    T0,
    create,
    events,
    post,
    processor,
    processor_server,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration._util import make_user, unique

pytestmark = pytest.mark.integration


def test_a_processor_turns_a_stream_into_another(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="doubled", blueprint="test-gain", params={"signals": ["x"]})
    wait_for(server, slug, "doubled", lambda p: p["state"] == "running")
    with watching(server, slug, "doubled") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 2.5}, {"y": 7}])
        got = samples_until(ws, lambda s: len(s) >= 3)
    assert [s["values"] for s in got] == [
        {"x": 2.0, "seen": 1.0},
        {"x": 5.0, "seen": 2.0},
        {"seen": 3.0},
    ]


def test_processors_chain_and_cannot_loop(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="first", blueprint="test-gain", params={"signals": ["x"]})
    create(
        server, slug, name="second", blueprint="test-gain", source="first",
        params={"signals": ["x"], "factor": 10.0},
    )  # fmt: skip
    for name in ("first", "second"):
        wait_for(server, slug, name, lambda p: p["state"] == "running")
    with watching(server, slug, "second") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 3.0}])
        got = samples_until(ws, lambda s: len(s) >= 2)
    assert [s["values"]["x"] for s in got] == [20.0, 60.0]
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/twins/{slug}/processors",
            json={"name": "back", "blueprint": "test-gain", "source": "second",
                  "output": "telemetry", "params": {"signals": ["x"]}},
        )  # fmt: skip
    assert r.status_code == 422 and "loop" in r.json()["detail"], r.text


def test_new_params_keep_the_state_and_other_changes_restart(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="g", blueprint="test-gain", params={"signals": ["x"]})
    before = wait_for(server, slug, "g", lambda p: p["state"] == "running")
    with watching(server, slug, "g") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 1.0}])
        samples_until(ws, lambda s: len(s) >= 2)
        with server.admin as admin:
            r = admin.patch(
                f"/api/v1/twins/{slug}/processors/g",
                json={"params": {"signals": ["x"], "factor": 3}},
            )
        assert r.status_code == 200 and r.json()["kept_state"] is True, r.text
        assert r.json()["pid"] == before["pid"]  # the same worker
        post(server, device, 2, [{"x": 1.0}], t0=T0 + 10 * MS)
        got = samples_until(ws, lambda s: len(s) >= 1)
    assert got[0]["values"] == {"x": 3.0, "seen": 3.0}  # counting went on
    with server.admin as admin:
        r = admin.patch(f"/api/v1/twins/{slug}/processors/g", json={"memory_limit_mb": 300})
    assert r.status_code == 200 and r.json()["kept_state"] is False, r.text
    after = wait_for(server, slug, "g", lambda p: p["state"] == "running")
    assert after["pid"] != before["pid"] and after["memory_limit_mb"] == 300
    assert after["stats"]["restarts"] == 0  # asked for, so not counted as a crash


def test_a_worker_over_its_memory_limit_is_restarted(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(
        server, slug, name="hog", blueprint="test-hog", memory_limit_mb=120,
        params={"signal": "x", "mb_per_sample": 16},
    )  # fmt: skip
    first = wait_for(server, slug, "hog", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}] * 12)  # 192 MB
    view = wait_for(server, slug, "hog", lambda p: p["stats"]["restarts"] >= 1)
    [event] = events(server, slug, "hog", "memory_limit")
    assert "over its memory limit" in event["message"] and event["data"]["rss_bytes"] > 120 * 2**20
    again = wait_for(server, slug, "hog", lambda p: p["state"] == "running")
    assert again["pid"] != first["pid"] and view["stats"]["crashes"] == 0


def test_an_exception_in_a_blueprint_is_recorded_and_the_worker_restarted(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="fussy", blueprint="test-fussy", params={"signal": "x"})
    create(server, slug, name="calm", blueprint="test-gain", params={"signals": ["x"]})
    for name in ("fussy", "calm"):
        wait_for(server, slug, name, lambda p: p["state"] == "running")
    with watching(server, slug, "calm") as ws:
        post(server, device, 1, [{"x": -1.0}])
        wait_for(server, slug, "fussy", lambda p: p["stats"]["restarts"] == 1)
        post(server, device, 2, [{"x": 4.0}], t0=T0 + 10 * MS)
        got = samples_until(ws, lambda s: len(s) >= 2)
    assert [s["values"]["x"] for s in got] == [-2.0, 8.0]  # the other processor went on
    [event] = events(server, slug, "fussy", "failed")
    assert "negative values are not allowed" in event["message"]
    assert event["data"]["restart_in_s"] > 0
    assert any("negative values" in line for line in event["data"]["log_tail"])
    wait_for(server, slug, "fussy", lambda p: p["state"] == "running")


def test_stop_start_and_delete(server: Server) -> None:
    slug, _ = device_twin(server)
    create(server, slug, name="g", blueprint="test-gain", params={"signals": ["x"]})
    wait_for(server, slug, "g", lambda p: p["state"] == "running")
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/g/stop")
        assert r.status_code == 200 and r.json()["state"] == "stopped", r.text
        assert r.json()["enabled"] is False
        kinds = [e["kind"] for e in events(server, slug, "g")]
        assert kinds[:2] == ["stopped", "started"]
        r = admin.post(f"/api/v1/twins/{slug}/processors/g/start")
        assert r.status_code == 200 and r.json()["enabled"] is True
        wait_for(server, slug, "g", lambda p: p["state"] == "running")
        assert admin.delete(f"/api/v1/twins/{slug}/processors/g").status_code == 204
        assert admin.get(f"/api/v1/twins/{slug}/processors/g").status_code == 404


@pytest.mark.parametrize(
    ("spec", "status", "words"),
    [
        ({"name": "p", "blueprint": "nope"}, 422, "no blueprint 'nope'"),
        ({"name": "p", "blueprint": "test-gain"}, 422, "signals"),
        ({"name": "p", "blueprint": "test-gain", "params": {"signals": ["x"], "typo": 1}}, 422,
         "typo"),
        ({"name": "P Q", "blueprint": "test-gain"}, 422, "name"),
        ({"name": "p", "blueprint": "test-gain", "params": {"signals": ["x"]},
          "output": "telemetry"}, 422, "cannot write the stream it reads"),
        ({"name": "p", "blueprint": "test-gain", "params": {"signals": ["x"]},
          "rates": {"min_input_spacing_s": -1}}, 422, "min_input_spacing_s"),
        ({"name": "p", "blueprint": "expression",
          "params": {"outputs": {"y": "x.__class__"}}}, 422, "attribute access is not allowed"),
        ({"name": "p", "blueprint": "lowpass", "params": {"signals": ["x"], "cutoff_hz": 80,
          "sample_rate_hz": 100}}, 422, "Nyquist"),
    ],
)  # fmt: skip
def test_bad_processors_are_refused_with_a_reason(
    server: Server, spec: dict[str, object], status: int, words: str
) -> None:
    slug, _ = device_twin(server)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors", json=spec)
    assert r.status_code == status and words in r.text, r.text


def test_rights(server: Server) -> None:
    slug, _ = device_twin(server)
    create(server, slug, name="g", blueprint="test-gain", params={"signals": ["x"]})
    name = unique("viewer")
    token = make_user(server, name)
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}/roles/{name}", json={"role": "viewer"})
        assert r.status_code == 200, r.text
    with server.client(token) as viewer:
        assert viewer.get(f"/api/v1/twins/{slug}/processors").status_code == 200
        assert viewer.get(f"/api/v1/twins/{slug}/processors/g/events").status_code == 200
        assert viewer.post(f"/api/v1/twins/{slug}/processors/g/stop").status_code == 403
        assert viewer.delete(f"/api/v1/twins/{slug}/processors/g").status_code == 403
    with server.client() as nobody:
        assert nobody.get("/api/v1/blueprints").status_code == 401
        assert nobody.get(f"/api/v1/twins/{slug}/processors").status_code == 401


def test_blueprints_are_listed_with_their_parameter_schema(server: Server) -> None:
    with server.admin as admin:
        r = admin.get("/api/v1/blueprints")
    assert r.status_code == 200
    by_name = {b["name"]: b for b in r.json()["blueprints"]}
    gain = by_name["test-gain"]
    assert gain["source"] == "folder" and gain["keeps_state"] is True
    assert gain["params_schema"]["properties"]["factor"]["description"] == "the gain"
    assert gain["params_schema"]["required"] == ["signals"]


def test_metrics_per_processor(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="m", blueprint="test-gain", params={"signals": ["x"]})
    wait_for(server, slug, "m", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}] * 5)
    view = wait_for(server, slug, "m", lambda p: p["stats"]["samples_out"] == 5)
    assert view["stats"]["samples_in"] == 5 and view["stats"]["rss_bytes"] > 0
    assert view["stats"]["step_time_s"]["p99"] > 0
    assert view["stats"]["added_latency_s"]["p50"] > 0
    with server.admin as admin:
        text = admin.get("/metrics").text
    labels = f'blueprint="test-gain",processor="m",twin="{slug}"'
    assert f"twinlink_processor_samples_out_total{{{labels}}} 5.0" in text


def test_a_hung_worker_is_restarted(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="stuck", blueprint="test-stuck", batch_timeout_s=0.5,
           params={"signal": "x"})  # fmt: skip
    first = wait_for(server, slug, "stuck", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}])
    wait_for(server, slug, "stuck", lambda p: p["stats"]["restarts"] == 1)
    [event] = events(server, slug, "stuck", "hung")
    assert "stuck on one batch" in event["message"]
    again = wait_for(server, slug, "stuck", lambda p: p["state"] == "running")
    assert again["pid"] != first["pid"]


def test_processors_come_back_after_a_server_restart(tmp_path: Path) -> None:
    server = processor_server(tmp_path)
    try:
        slug, [device] = device_twin(server)
        create(server, slug, name="on", blueprint="test-gain", params={"signals": ["x"]})
        create(server, slug, name="off", blueprint="test-gain", params={"signals": ["x"]},
               enabled=False)  # fmt: skip
        wait_for(server, slug, "on", lambda p: p["state"] == "running")
        pid = processor(server, slug, "on")["pid"]
    finally:
        stop_server(server)
    assert not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
    server = restart_server(server, {"TWINLINK_BLUEPRINTS_DIR": str(BLUEPRINTS)})
    try:
        wait_for(server, slug, "on", lambda p: p["state"] == "running")
        assert processor(server, slug, "off")["state"] == "stopped"
        with watching(server, slug, "on") as ws:
            post(server, device, 5, [{"x": 2.0}])
            [sample] = samples_until(ws, lambda s: len(s) >= 1)
        assert sample["values"] == {"x": 4.0, "seen": 1.0}
    finally:
        stop_server(server)


def test_a_worker_that_does_not_stop_is_stopped_by_force(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="stuck", blueprint="test-stuck", params={"signal": "x"})
    pid = wait_for(server, slug, "stuck", lambda p: p["state"] == "running")["pid"]
    post(server, device, 1, [{"x": 1.0}])  # the worker never returns from this batch
    wait_for(server, slug, "stuck", lambda p: p["stats"]["samples_in"] == 1)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/stuck/stop")
    assert r.status_code == 200 and r.json()["state"] == "stopped", r.text
    assert not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
    assert events(server, slug, "stuck", "hung") == []  # a stop, not a crash


def test_new_inputs_are_read_from_the_next_batch(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="g", blueprint="test-gain", params={"signals": ["x"]})
    wait_for(server, slug, "g", lambda p: p["state"] == "running")
    with server.admin as admin:
        changes = {"inputs": {"x": {"signal": "y", "scale": 10}}, "output": "g2"}
        r = admin.patch(f"/api/v1/twins/{slug}/processors/g", json=changes)
    assert r.status_code == 200 and r.json()["kept_state"] is False, r.text
    wait_for(server, slug, "g", lambda p: p["state"] == "running")
    with watching(server, slug, "g2") as ws:
        post(server, device, 1, [{"x": 1.0, "y": 0.5}])
        [sample] = samples_until(ws, lambda s: len(s) >= 1)
    assert sample["values"] == {"x": 10.0, "seen": 1.0}  # 0.5 * 10 * 2, in the new stream


def test_workers_do_not_see_the_servers_settings(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="snoop", blueprint="test-snoop", params={"signal": "x"})
    wait_for(server, slug, "snoop", lambda p: p["state"] == "running")
    with watching(server, slug, "snoop") as ws:
        post(server, device, 1, [{"x": 1.0}])
        [sample] = samples_until(ws, lambda s: len(s) >= 1)
    assert sample["values"] == {"settings_seen": 0.0}  # the server has TWINLINK_ADMIN_TOKEN


def test_the_server_runs_at_most_max_processors(tmp_path: Path) -> None:
    small = processor_server(tmp_path, TWINLINK_MAX_PROCESSORS="1")
    try:
        slug, _ = device_twin(small)
        create(small, slug, name="one", blueprint="test-gain", params={"signals": ["x"]})
        with small.admin as admin:
            spec = {"name": "two", "blueprint": "test-gain", "params": {"signals": ["x"]}}
            r = admin.post(f"/api/v1/twins/{slug}/processors", json=spec)
            assert r.status_code == 409 and "TWINLINK_MAX_PROCESSORS" in r.text, r.text
            r = admin.post(f"/api/v1/twins/{slug}/processors", json={**spec, "enabled": False})
            assert r.status_code == 201, r.text
            assert admin.post(f"/api/v1/twins/{slug}/processors/two/start").status_code == 409
            assert admin.post(f"/api/v1/twins/{slug}/processors/one/stop").status_code == 200
            r = admin.post(f"/api/v1/twins/{slug}/processors/two/start")
            assert r.status_code == 200 and r.json()["enabled"] is True, r.text
    finally:
        stop_server(small)
