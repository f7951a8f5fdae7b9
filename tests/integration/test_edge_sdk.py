"""The device SDK (twinlink_edge) against the real server: samples are acknowledged and stored,
commands reach their handlers and their results come back, desired and reported properties
travel both ways. The thesis's `digitalTwinPlt` code through the compat module is in
test_edge_compat.py."""

from __future__ import annotations

import queue
from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import device_twin
from twinlink_edge import AsyncDevice, Device

pytestmark = pytest.mark.integration

TIMEOUT = 30.0
BASE_NS = 1_800_000_000_000_000_000


def history(server: Server, slug: str, stream: str = "telemetry") -> list[dict[str, Any]]:
    """Every stored row of a stream, through the history API, a page at a time."""
    rows: list[dict[str, Any]] = []
    params: dict[str, Any] = {"start": "1970-01-01T00:00:00Z", "limit": 100_000}
    with server.admin as admin:
        while True:
            r = admin.get(f"/api/v1/twins/{slug}/streams/{stream}/samples", params=params)
            assert r.status_code == 200, r.text
            rows += r.json()["rows"]
            if not r.json()["next_cursor"]:
                return rows
            params["cursor"] = r.json()["next_cursor"]


def command(admin: httpx.Client, slug: str, name: str, **args: Any) -> dict[str, Any]:
    body = {"name": name, "args": args, "wait": True, "timeout_s": TIMEOUT}
    r = admin.post(f"/api/v1/twins/{slug}/commands", json=body)
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_samples_are_acked_and_stored_once_each(server: Server) -> None:
    slug, (token,) = device_twin(server)
    acks = []
    with Device(server.url, token, batch_size=500, on_ack=acks.append) as dev:
        for i in range(3000):
            dev.add({"x": i, "label": f"s{i % 3}"}, time_ns=BASE_NS + i)
        dev.add({"x": None}, time_ns=BASE_NS + 3000)  # refused by the server: null
        dev.flush(TIMEOUT)
        assert (dev.acked_samples, dev.rejected, dev.buffered_samples) == (3001, 1, 0)
        assert dev.stats()["accepted_samples"] == 3000 and dev.device_name == "dev0"
    # Batch boundaries depend on when the sender wakes; the refused sample is
    # the last one sent, so it is the last of whichever batch carried it.
    assert sum(a.accepted for a in acks) == 3000
    assert all(a.accepted + len(a.rejected) <= 500 for a in acks)
    (last,) = [a for a in acks if a.rejected]
    assert last.rejected == [(last.accepted, "x: None is not a number, bool or string")]
    rows = history(server, slug)
    assert [row["values"]["x"] for row in rows] == list(range(3000))
    assert rows[7] == {"time": BASE_NS + 7, "values": {"x": 7, "label": "s1"}}


async def test_the_async_device_pipelines_many_batches(server: Server) -> None:
    slug, (token,) = device_twin(server)
    async with AsyncDevice(server.url, token, batch_size=250, window=16) as dev:
        for i in range(20_000):
            await dev.send({"n": i}, time_ns=BASE_NS + i)
        await dev.flush(TIMEOUT)
        assert dev.accepted_samples == 20_000 and dev.connections == 1
    with server.admin as admin:
        streams = admin.get(f"/api/v1/twins/{slug}/streams").json()
    assert "'count': 20000" in str(streams), streams


def test_commands_reach_their_handlers_and_results_come_back(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with Device(server.url, token) as dev, server.admin as admin:

        @dev.on_command("set_k")
        def set_k(args: dict[str, Any]) -> dict[str, Any]:
            return {"k": args["k"] * 2}

        @dev.on_command("boom")
        async def boom(args: dict[str, Any]) -> None:
            raise RuntimeError("the rig is on fire")

        assert dev.wait_connected(TIMEOUT)
        done = command(admin, slug, "set_k", k=21)
        assert (done["state"], done["result"]) == ("succeeded", {"k": 42})
        failed = command(admin, slug, "boom")
        assert (failed["state"], failed["error"]) == ("failed", "the rig is on fire")
        unknown = command(admin, slug, "nope")
        assert (unknown["state"], unknown["error"]) == ("failed", "no handler for command 'nope'")


def test_desired_properties_reach_the_device_and_reports_come_back(server: Server) -> None:
    slug, (token,) = device_twin(server)
    props = f"/api/v1/twins/{slug}/devices/dev0/properties"
    seen: queue.Queue[dict[str, Any]] = queue.Queue()
    with server.admin as admin:
        # Set while the device is away: it hears of it in its welcome.
        assert admin.patch(f"{props}/desired", json={"K": 0.85}).status_code == 200
        with Device(server.url, token) as dev:
            dev.on_desired(seen.put)
            assert seen.get(timeout=TIMEOUT) == {"K": 0.85}
            assert admin.patch(f"{props}/desired", json={"mode": "fast"}).status_code == 200
            assert seen.get(timeout=TIMEOUT) == {"K": 0.85, "mode": "fast"}
            assert dev.desired == {"K": 0.85, "mode": "fast"}
            version = dev.report({"K": 0.85, "mode": "fast"}, timeout=TIMEOUT)
            assert isinstance(version, int) and dev.desired == {}
        shown = admin.get(props).json()
    assert shown["delta"] == {} and shown["reported"]["K"]["value"] == 0.85
