"""The UDP connector between the socket and the platform, without a socket: who may send,
what is counted, and how datagrams become batches."""

from __future__ import annotations

import asyncio
import struct
from collections.abc import AsyncIterator
from typing import Any, cast

import pytest

from twinlink.connectors.base import ConnectorTransport
from twinlink.connectors.udp import connector as udp
from twinlink.connectors.udp.connector import SenderFilter, UdpConnector
from twinlink.domain.records import Device
from twinlink.ingest.link import DeviceLink

DEVICE = Device(1, 1, "rig", "catman", "", "tld_", 0, None)


class FakeLink:
    """Records the messages a real DeviceLink would dispatch."""

    def __init__(self) -> None:
        self.session = type("Session", (), {"closed": asyncio.Event()})()
        self.batches: list[dict[str, Any]] = []
        self.arrived = asyncio.Event()
        self.fail_next = False

    async def dispatch(self, message: dict[str, Any]) -> None:
        if self.fail_next:
            self.fail_next = False
            raise RuntimeError("the store is away")
        self.batches.append(message)
        self.arrived.set()

    async def wait_for_samples(self, count: int) -> list[dict[str, Any]]:
        async with asyncio.timeout(5):
            while sum(len(b["samples"]) for b in self.batches) < count:
                self.arrived.clear()
                await self.arrived.wait()
        return self.batches


class FakeHost:
    device = DEVICE

    def __init__(self) -> None:
        self.link = FakeLink()

    async def connect(self, transport: ConnectorTransport) -> DeviceLink:
        return cast(DeviceLink, self.link)

    async def disconnect(self, link: DeviceLink) -> None:
        return None


def connector(**fields: Any) -> tuple[UdpConnector, FakeLink]:
    host = FakeHost()
    settings = {"port": 0, "byte_format": "<d", "channels": ["x"], **fields}
    return UdpConnector("rig-udp", UdpConnector.Config.model_validate(settings), host), host.link


def record(x: float) -> bytes:
    return struct.pack("<d", x)


@pytest.fixture
async def running() -> AsyncIterator[list[asyncio.Task[None]]]:
    """Tasks of `run` started by a test, cancelled after it."""
    tasks: list[asyncio.Task[None]] = []
    yield tasks
    for task in tasks:
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)


async def test_datagrams_read_together_go_as_one_batch(running: list[asyncio.Task[None]]) -> None:
    c, link = connector(batch_window_ms=0)
    for i in range(5):
        c.receive(record(i), "127.0.0.1")
    running.append(asyncio.create_task(c.run()))
    [batch] = await link.wait_for_samples(5)
    assert batch["type"] == "samples" and batch["stream"] == "telemetry"
    assert [s["values"]["x"] for s in batch["samples"]] == [0, 1, 2, 3, 4]
    view = c.status.view()
    # (the state is set by prepare(), which binds the socket; not run here)
    assert (view["messages"], view["samples"], view["errors"]) == (5, 5, {})


async def test_a_full_batch_goes_at_once_in_pieces_of_the_largest_size(
    running: list[asyncio.Task[None]],
) -> None:
    c, link = connector(batch_window_ms=1000, batch_max_samples=2)
    for i in range(5):
        c.receive(record(i), "127.0.0.1")
    running.append(asyncio.create_task(c.run()))
    batches = await link.wait_for_samples(5)  # long before the 1 s window ends
    assert [len(b["samples"]) for b in batches] == [2, 2, 1]
    assert len({b["seq"] for b in batches}) == 3


async def test_samples_read_before_a_stop_still_go(running: list[asyncio.Task[None]]) -> None:
    c, link = connector(batch_window_ms=1000)
    task = asyncio.create_task(c.run())
    running.append(task)
    await asyncio.sleep(0)  # one loop turn: the task has started and waits for datagrams
    c.receive(record(1.5), "127.0.0.1")  # waits for its 1 s window
    task.cancel()
    await asyncio.gather(task, return_exceptions=True)
    assert [b["samples"][0]["values"] for b in link.batches] == [{"x": 1.5}]


async def test_a_refused_sender_and_a_malformed_datagram_are_counted_by_kind() -> None:
    c, _ = connector(allowed_senders=["10.1.0.0/16"])
    c.receive(record(1), "10.2.0.1")
    c.receive(b"\x00\x01", "10.1.2.3")
    c.receive(record(2), "10.1.2.3")
    view = c.status.view()
    assert view["errors"] == {"refused_sender": 1, "truncated": 1}
    assert view["last_error"] == (
        "truncated: 2 bytes, shorter than one record of '<d' (8 bytes) (from 10.1.2.3)"
    )
    assert view["messages"] == 1 and len(c._pending) == 1


async def test_beyond_the_pending_limit_datagrams_are_dropped_and_counted(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(udp, "MAX_PENDING", 3)
    c, _ = connector()
    c.receive(struct.pack("<ddd", 1, 2, 3), "127.0.0.1")
    c.receive(record(4), "127.0.0.1")
    assert c.status.errors == {"overflow": 1} and len(c._pending) == 3


async def test_a_decoder_bug_is_counted_and_the_listener_goes_on(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    c, _ = connector()

    def broken(data: bytes, arrival_ns: int) -> list[dict[str, Any]]:
        raise ZeroDivisionError("oops")

    monkeypatch.setattr(c.decoder, "decode", broken)
    c.receive(record(1), "127.0.0.1")
    assert c.status.errors == {"decode_failed": 1}
    assert "ZeroDivisionError: oops" in str(c.status.last_error)


async def test_a_batch_that_cannot_be_handed_over_is_counted_and_the_next_goes(
    running: list[asyncio.Task[None]], caplog: pytest.LogCaptureFixture
) -> None:
    c, link = connector(batch_window_ms=0)
    link.fail_next = True
    c.receive(record(1), "127.0.0.1")
    running.append(asyncio.create_task(c.run()))
    async with asyncio.timeout(5):
        while not c.status.errors:
            await asyncio.sleep(0)
    assert c.status.last_error == "send_failed: 1 samples lost: the store is away"
    c.receive(record(2), "127.0.0.1")
    [batch] = await link.wait_for_samples(1)
    assert batch["samples"][0]["values"] == {"x": 2}


def test_a_sender_filter_takes_addresses_networks_and_mapped_ipv4() -> None:
    senders = SenderFilter(["127.0.0.1", "192.168.1.0/24", "fe80::/10"])
    assert senders.allows("127.0.0.1") and senders.allows("192.168.1.77")
    assert senders.allows("::ffff:192.168.1.5")  # IPv4 on a dual-stack socket
    assert senders.allows("fe80::1%eth0")
    assert not senders.allows("127.0.0.2") and not senders.allows("192.168.2.1")
    assert not senders.allows("not-an-address") and not senders.allows("::1")


def test_the_status_shows_the_address_listened_on() -> None:
    c, _ = connector()
    assert c.status.view()["address"] is None
    assert c.kind == "udp" and "struct" in (UdpConnector.__doc__ or "")
