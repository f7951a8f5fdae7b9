"""Crash test: `kill -9` the server while four SDK devices stream, then restart it.

Every sample a device was acknowledged for must be in history exactly once, and the devices
must resume on their own (their unacknowledged batches are resent; the sequence numbers make
the resend harmless), so in the end every sample sent is stored exactly once.
"""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._live import device_twin, stored_values
from twinlink_edge.aio import AsyncDevice

pytestmark = pytest.mark.integration

DEVICES = 4
PER_TICK = 50  # samples each device adds per loop turn


@pytest.fixture
def crash_server(tmp_path: Path) -> Iterator[list[Server]]:
    servers = [start_server(tmp_path / "data")]
    try:
        yield servers
    finally:
        for server in servers:
            stop_server(server)


async def _produce(device: AsyncDevice, name: str, counter: list[int], stop: asyncio.Event) -> None:
    base = 1_800_000_000_000_000_000
    while not stop.is_set():
        for _ in range(PER_TICK):
            n = counter[0]
            await device.send({f"n_{name}": n}, time_ns=base + n)
            counter[0] += 1
        await asyncio.sleep(0)  # yield to the SDK's sender between bursts


async def _until(condition: object, timeout: float = 60) -> None:
    async def poll() -> None:
        while not condition():  # type: ignore[operator]
            await asyncio.sleep(0.01)

    await asyncio.wait_for(poll(), timeout)


async def test_kill_9_loses_nothing_acknowledged_and_devices_resume(
    crash_server: list[Server],
) -> None:
    server = crash_server[0]
    slug, tokens = await asyncio.to_thread(device_twin, server, None, DEVICES)
    devices = [
        AsyncDevice(server.url, token, batch_size=200, flush_interval=0.01, backoff_max=0.5)
        for token in tokens
    ]
    counters = [[0] for _ in devices]
    stop = asyncio.Event()
    for device in devices:
        await device.start()
    producers = [
        asyncio.create_task(_produce(d, f"dev{i}", counters[i], stop))
        for i, d in enumerate(devices)
    ]
    try:
        await _until(lambda: all(d.accepted_samples >= 2000 for d in devices))
        acked_before_kill = [d.accepted_samples for d in devices]
        connections = [d.connections for d in devices]
        server.process.kill()  # SIGKILL: no shutdown, no flush
        await asyncio.to_thread(server.process.wait)
        stop_server(server)
        restarted = await asyncio.to_thread(restart_server, server)
        crash_server.append(restarted)
        # Acknowledged before the kill means durable: it is there before any resend lands.
        for i, acked in enumerate(acked_before_kill):
            assert (
                len(await asyncio.to_thread(stored_values, restarted, slug, f"n_dev{i}")) >= acked
            )
        await _until(
            lambda: all(d.connections > c for d, c in zip(devices, connections, strict=True))
        )
        stop.set()
        await asyncio.gather(*producers)
        for device in devices:
            await device.flush(timeout=60)
    finally:
        stop.set()
        for device in devices:
            await device.close()
    for i, counter in enumerate(counters):
        values = await asyncio.to_thread(stored_values, restarted, slug, f"n_dev{i}")
        assert len(values) == len(set(values)), f"dev{i}: a sample is stored twice"
        assert sorted(values) == list(range(counter[0])), f"dev{i}: samples are missing"
        assert devices[i].accepted_samples >= counter[0]
