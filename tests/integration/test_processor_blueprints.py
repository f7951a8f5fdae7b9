"""Built-in and Tvilling digital style blueprints on a real server: the alarm that closes the
loop by commanding the device, and a blueprint written for the original platform."""

from __future__ import annotations

import asyncio

import pytest

from tests.conftest import Server
from tests.integration._device import FakeDevice
from tests.integration._live import device_twin
from tests.integration._processors import (
    MS,
    T0,
    create,
    events,
    post,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture

pytestmark = pytest.mark.integration


async def test_an_alarm_sends_a_command_to_the_device(server: Server) -> None:
    slug, [token] = device_twin(server)
    create(
        server, slug, name="guard", blueprint="trigger",
        params={"signal": "x", "high": 5.0, "clear_at": 4.0,
                "command": {"name": "pause", "params": {"why": "x too high"}}},
    )  # fmt: skip
    await asyncio.to_thread(wait_for, server, slug, "guard", lambda p: p["state"] == "running")
    async with FakeDevice(server, token) as device:
        await device.send(
            {"type": "samples", "seq": 1,
             "samples": [{"time": T0 + i * MS, "values": {"x": x}}
                         for i, x in enumerate([1.0, 6.0, 7.0, 4.5, 3.0])]},
        )  # fmt: skip
        command = await device.next("command")
    assert command["name"] == "pause" and command["args"] == {"why": "x too high"}
    kinds = [e["kind"] for e in await asyncio.to_thread(events, server, slug, "guard")]
    assert "alarm" in kinds and "alarm_cleared" in kinds
    [alarm] = await asyncio.to_thread(events, server, slug, "guard", "alarm")
    assert alarm["time_ns"] == T0 + MS and alarm["data"]["value"] == 6.0


def test_a_tvilling_digital_blueprint_runs_unchanged(server: Server) -> None:
    slug, [device] = device_twin(server)
    with server.admin as admin:
        listed = {b["name"]: b for b in admin.get("/api/v1/blueprints").json()["blueprints"]}
    schema = listed["tvilling_style"]["params_schema"]["properties"]
    assert schema["time_constant"]["default"] == 0.5
    assert "time constant" in schema["time_constant"]["description"]
    create(
        server, slug, name="smooth", blueprint="tvilling_style",
        inputs={"measurement": {"signal": "x", "scale": 2.0}},  # the measurement_proportion
        params={"mode": "hold"},
    )  # fmt: skip
    wait_for(server, slug, "smooth", lambda p: p["state"] == "running")
    with watching(server, slug, "smooth") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 2.0}, {"x": 3.0}])
        got = samples_until(ws, lambda s: len(s) >= 3)
    assert [s["values"]["smoothed"] for s in got] == [2.0, 4.0, 6.0]
    assert [s["values"]["steps"] for s in got] == [1.0, 2.0, 3.0]
    assert [s["time"] for s in got] == [T0, T0 + MS, T0 + 2 * MS]


def test_filter_and_expression_chain(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="smoothed", blueprint="lowpass",
           params={"signals": ["x"], "cutoff_hz": 5.0, "sample_rate_hz": 1000.0})  # fmt: skip
    outputs = {"stress": "x * 1000 + 1", "alarm": "where(x > 0.5, 1, 0)"}
    create(server, slug, name="derived", blueprint="expression", source="smoothed",
           params={"outputs": outputs})  # fmt: skip
    for name in ("smoothed", "derived"):
        wait_for(server, slug, name, lambda p: p["state"] == "running")
    with watching(server, slug, "derived") as ws:
        post(server, device, 1, [{"x": 1.0}] * 50)
        got = samples_until(ws, lambda s: len(s) >= 50)
    # a step of 1.0 through a 5 Hz low-pass settled from its first value: it stays at 1.0
    assert all(abs(s["values"]["stress"] - 1001.0) < 1e-6 for s in got)
    assert {s["values"]["alarm"] for s in got} == {1.0}
