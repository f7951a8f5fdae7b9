"""/readyz and /healthz over a store that stops answering: 503 naming the store within the
bound (never a hang), one ping in flight however many probes come, ready again once the store
answers (api/readiness.py, api/system.py)."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import httpx
import pytest
from fastapi import FastAPI

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.api import system
from twinlink.api.problems import install
from twinlink.api.readiness import Readiness
from twinlink.bus.memory import MemoryBus

BOUND_S = 0.2  # TWINLINK_READY_TIMEOUT_S here: short, so a stuck check ends the test fast


class StuckStore:
    """A store whose ping waits until `release` is set (a database stopped with SIGSTOP)."""

    def __init__(self) -> None:
        self.release = asyncio.Event()
        self.release.set()
        self.pings = 0
        self.underway = 0

    async def ping(self) -> bool:
        self.pings += 1
        self.underway += 1
        try:
            await self.release.wait()
        finally:
            self.underway -= 1
        return True


class Bus(MemoryBus):
    def __init__(self) -> None:
        super().__init__()
        self.usable = True

    async def ready(self) -> bool:
        return self.usable


@asynccontextmanager
async def client(store: object, bus: object) -> AsyncIterator[httpx.AsyncClient]:
    app = FastAPI(version="9.9.9")
    install(app)
    app.include_router(system.router)
    readiness = app.state.readiness = Readiness(store, bus, BOUND_S)  # type: ignore[arg-type]
    transport = httpx.ASGITransport(app=app)
    try:
        async with httpx.AsyncClient(transport=transport, base_url="http://node") as c:
            yield c
    finally:
        await readiness.close()


def assert_not_ready(r: httpx.Response, detail: str) -> None:
    assert r.status_code == 503, r.text
    assert r.headers["content-type"].startswith("application/problem+json")
    assert r.json()["detail"] == detail


async def test_ready_on_sqlite(stores: Stores) -> None:
    async with client(stores.metadata, MemoryBus()) as c:
        r = await c.get("/readyz")
        health = await c.get("/healthz")
    assert r.status_code == 200, r.text
    assert r.json() == {"status": "ready", "version": "9.9.9"}
    assert health.json() == {"status": "ok", "version": "9.9.9"}


async def test_a_store_that_stops_answering_is_not_ready_then_ready_again() -> None:
    store = StuckStore()
    async with client(store, MemoryBus()) as c:
        assert (await c.get("/readyz")).status_code == 200
        store.release.clear()  # the database stops answering
        r = await c.get("/readyz")
        assert_not_ready(r, "the store does not answer within 0.2 s")
        assert_not_ready(await c.get("/healthz"), "the store does not answer within 0.2 s")
        store.release.set()  # and answers again
        r = await c.get("/readyz")
        assert r.status_code == 200, r.text
        assert (await c.get("/healthz")).status_code == 200


async def test_becoming_not_ready_and_ready_again_is_logged_once_each(
    caplog: pytest.LogCaptureFixture,
) -> None:
    store = StuckStore()
    with caplog.at_level(logging.INFO, logger="twinlink.api"):
        async with client(store, MemoryBus()) as c:
            await c.get("/readyz")
            store.release.clear()
            for _ in range(3):
                await c.get("/readyz")
            store.release.set()
            for _ in range(3):
                await c.get("/readyz")
    events = [(r.levelname, getattr(r, "event", None)) for r in caplog.records]
    assert events == [("WARNING", "not_ready"), ("INFO", "ready_again")]
    assert caplog.records[0].getMessage() == "not ready: the store does not answer within 0.2 s"


async def test_probes_share_one_ping_in_flight() -> None:
    store = StuckStore()
    store.release.clear()
    async with client(store, MemoryBus()) as c:
        answers = await asyncio.gather(*(c.get("/readyz") for _ in range(20)))
        assert {r.status_code for r in answers} == {503}
        assert store.pings == 1  # twenty probes, one ping
        store.release.set()
        r = await c.get("/readyz")
    assert r.status_code == 200, r.text
    assert store.underway == 0


async def test_a_ping_cancelled_at_the_bound_is_not_sent_again_while_it_ends() -> None:
    """A ping that does not end when cancelled (a driver cleaning its connection up) stays the
    one in flight: later probes wait for it instead of sending more."""
    gate = asyncio.Event()
    pings = 0

    async def ping() -> bool:
        nonlocal pings
        pings += 1
        try:
            await asyncio.Event().wait()  # never answers
        except asyncio.CancelledError:
            await gate.wait()  # the cleanup takes until the database is back
            raise
        return True

    class Store:
        async def ping(self) -> bool:
            return await ping()

    async with client(Store(), MemoryBus()) as c:
        for _ in range(3):
            assert_not_ready(await c.get("/readyz"), "the store does not answer within 0.2 s")
        assert pings == 1
        gate.set()  # the cancelled ping ends: the next probe waits for it or starts anew
        for _ in range(2):
            assert_not_ready(await c.get("/readyz"), "the store does not answer within 0.2 s")
    assert pings >= 2  # once the old flight ended, probes ping again


async def test_a_bus_not_connected_is_not_ready_and_healthz_still_ok() -> None:
    bus = Bus()
    bus.usable = False
    async with client(StuckStore(), bus) as c:
        r = await c.get("/readyz")
        health = await c.get("/healthz")
        bus.usable = True
        again = await c.get("/readyz")
    assert_not_ready(r, "the bus is not connected (no answer within 0.2 s)")
    assert health.status_code == 200  # /healthz is the store's liveness, as before
    assert again.status_code == 200


async def test_a_store_and_bus_both_down_are_both_named() -> None:
    class Broken:
        async def ping(self) -> bool:
            raise OSError("connection refused")

    bus = Bus()
    bus.usable = False
    async with client(Broken(), bus) as c:
        r = await c.get("/readyz")
    assert_not_ready(
        r,
        "the store does not answer within 0.2 s; the bus is not connected (no answer within 0.2 s)",
    )
