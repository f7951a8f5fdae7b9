"""UDP datasources on real sockets, in a real platform built in-process: catman records, a
custom struct format and JSON reach the bus and history; refused senders, truncated and
garbage datagrams are counted while the good ones still arrive; a port in use is a clear
error; a stopped connector frees its port."""

from __future__ import annotations

import asyncio
import socket
import struct
import time
from collections.abc import AsyncIterator, Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import orjson
import pytest

from twinlink.app import Services, build_services, start_services, stop_services
from twinlink.auth.rights import Principal
from twinlink.bus import samples_subject
from twinlink.config import Settings
from twinlink.connectors.base import ConnectorError, LinkHost
from twinlink.connectors.udp.connector import UdpConnector
from twinlink.domain.records import Device
from twinlink.domain.samples import SampleBatch
from twinlink.domain.yamlsource import SourceDocument

pytestmark = pytest.mark.integration

INTERFACE = {
    "signals": [
        {"name": "strain", "type": "number"},
        {"name": "force", "type": "number", "min": -100, "max": 100},
        {"name": "angle", "type": "number"},
        {"name": "level", "type": "integer"},
    ]
}


@dataclass
class Platform:
    services: Services
    device: Device
    seen: list[SampleBatch] = field(default_factory=list)
    arrived: asyncio.Event = field(default_factory=asyncio.Event)
    connectors: list[UdpConnector] = field(default_factory=list)

    async def connector(self, **config: Any) -> UdpConnector:
        settings = UdpConnector.Config.model_validate({"host": "127.0.0.1", "port": 0, **config})
        host = LinkHost(self.services.device_hub, self.services.ingest, self.device)
        c = UdpConnector("rig-udp", settings, host)
        await c.start()
        self.connectors.append(c)
        await until(lambda: c.status.state == "listening")
        return c

    async def samples(self, count: int) -> list[dict[str, Any]]:
        """The first `count` samples on the bus (published once durable)."""
        async with asyncio.timeout(10):
            while sum(len(b) for b in self.seen) < count:
                self.arrived.clear()
                await self.arrived.wait()
        rows = [
            {"time": t, "values": v}
            for b in self.seen
            for t, v in zip(b.times, b.values, strict=True)
        ]
        return rows[:count]


async def until(condition: Callable[[], bool]) -> None:
    """Wait until `condition` holds (state changed by the event loop), at most 10 s."""
    async with asyncio.timeout(10):
        while not condition():
            await asyncio.sleep(0.001)


@pytest.fixture
async def platform(tmp_path: Path) -> AsyncIterator[Platform]:
    settings = Settings(data_dir=tmp_path / "data", history_sync="normal", mqtt_mode="off")
    services = build_services(settings)
    await start_services(services, settings)
    try:
        admin = await services.store.get_user_by_name("admin")
        assert admin is not None
        doc = {"version": "1.0", "privacy": "public", "id": "urn:rig", "interface": INTERFACE}
        [applied] = await services.registry.apply(Principal(admin), [SourceDocument(doc)])
        device, _ = await services.devices.create(Principal(admin), applied.twin.slug, "daq", "")
        p = Platform(services, device)

        def seen(subject: str, message: object) -> None:
            assert isinstance(message, SampleBatch)
            p.seen.append(message)
            p.arrived.set()

        unsubscribe = services.bus.subscribe(samples_subject(device.twin_id, "telemetry"), seen)
        yield p
        unsubscribe()
        for c in p.connectors:
            await c.stop()
    finally:
        await stop_services(services)


@pytest.fixture
def sender() -> Iterator[Callable[..., socket.socket]]:
    """`sender(host)`: a UDP socket bound to `host` (any 127.x address works on Linux)."""
    made: list[socket.socket] = []

    def make(host: str = "127.0.0.1") -> socket.socket:
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.bind((host, 0))
        made.append(sock)
        return sock

    yield make
    for sock in made:
        sock.close()


def catman(counter: int, *values: float) -> bytes:
    return struct.pack(f"<HHI{len(values)}d", 1, len(values), counter, *values)


async def test_catman_records_reach_the_bus_and_history(
    platform: Platform, sender: Callable[..., socket.socket]
) -> None:
    c = await platform.connector(
        format="catman", channels=["time", "strain", "force"], time_channel="time",
        time_origin="start",
    )  # fmt: skip
    assert c.address is not None and c.status.view()["address"] == f"127.0.0.1:{c.address[1]}"
    before = time.time_ns()
    out = sender()
    # Two datagrams of two records each, 10 ms apart by catman's clock.
    out.sendto(catman(1, 0.00, 1e-4, 2.5) + catman(2, 0.01, 2e-4, 2.75), c.address)
    out.sendto(catman(3, 0.02, 3e-4, 3.0) + catman(4, 0.03, 4e-4, 3.25), c.address)
    samples = await platform.samples(4)
    assert [s["values"]["force"] for s in samples] == [2.5, 2.75, 3.0, 3.25]
    first = samples[0]["time"]
    assert before <= first <= time.time_ns()  # anchored at the first datagram's arrival
    assert [s["time"] - first for s in samples] == [0, 10_000_000, 20_000_000, 30_000_000]
    page = await platform.services.history.samples(
        platform.device.twin_id, "telemetry", ["strain", "force"], first, first + 10**9, 10
    )
    assert [row["values"]["strain"] for row in page.rows] == [1e-4, 2e-4, 3e-4, 4e-4]
    view = c.status.view()
    assert (view["messages"], view["samples"], view["errors"]) == (2, 4, {})


async def test_a_custom_struct_format_with_an_epoch_time(
    platform: Platform, sender: Callable[..., socket.socket]
) -> None:
    c = await platform.connector(
        byte_format=">Qfxh", channels=["t", "angle", "level"], time_channel="t", time_unit="ns"
    )
    stamp = 1_750_000_000_123_456_789
    assert c.address is not None
    sender().sendto(struct.pack(">Qfxh", stamp, 0.5, -3), c.address)
    [sample] = await platform.samples(1)
    assert sample == {"time": stamp, "values": {"angle": 0.5, "level": -3}}


async def test_json_datagrams_flat_and_batch(
    platform: Platform, sender: Callable[..., socket.socket]
) -> None:
    c = await platform.connector(format="json", time_unit="ms")
    assert c.address is not None
    out = sender()
    out.sendto(orjson.dumps({"force": 1.5, "time": 1_750_000_000_000}), c.address)
    await platform.samples(1)
    batch = {"samples": [{"time": 1_750_000_000_001, "values": {"force": 2.5}},
                         {"time": 1_750_000_000_002, "values": {"force": 3.5}}]}  # fmt: skip
    out.sendto(orjson.dumps(batch), c.address)
    samples = await platform.samples(3)
    assert [(s["time"], s["values"]["force"]) for s in samples] == [
        (1_750_000_000_000_000_000, 1.5),
        (1_750_000_000_001_000_000, 2.5),
        (1_750_000_000_002_000_000, 3.5),
    ]


async def test_a_sender_not_allowed_is_refused_and_counted(
    platform: Platform, sender: Callable[..., socket.socket]
) -> None:
    c = await platform.connector(format="json", allowed_senders=["127.0.0.1/32"])
    assert c.address is not None
    sender("127.0.0.2").sendto(b'{"force": 66}', c.address)
    await until(lambda: c.status.errors["refused_sender"] == 1)
    sender("127.0.0.1").sendto(b'{"force": 1}', c.address)
    [sample] = await platform.samples(1)
    assert sample["values"] == {"force": 1}
    assert (
        c.status.last_error == "refused_sender: a datagram from 127.0.0.2, not in allowed_senders"
    )


async def test_malformed_datagrams_are_counted_and_the_good_ones_between_arrive(
    platform: Platform, sender: Callable[..., socket.socket]
) -> None:
    c = await platform.connector(byte_format="<dd", channels=["force", "angle"])
    assert c.address is not None
    out = sender()
    out.sendto(struct.pack("<dd", 1.0, 0.1), c.address)
    out.sendto(struct.pack("<dd", 2.0, 0.2)[:-4], c.address)  # truncated
    out.sendto(b"\x00" * 20, c.address)  # not a whole number of records
    out.sendto(struct.pack("<dd", 3.0, 0.3), c.address)
    out.sendto(struct.pack("<dd", float("nan"), 0.4), c.address)
    out.sendto(struct.pack("<dd", 500.0, 0.5), c.address)  # out of the interface's range
    out.sendto(struct.pack("<dd", 4.0, 0.6), c.address)
    samples = await platform.samples(3)
    assert [s["values"]["force"] for s in samples] == [1.0, 3.0, 4.0]
    await until(lambda: c.status.rejected == 1)  # the platform's ack says why
    assert c.status.errors == {"truncated": 1, "wrong_size": 1, "nan": 1, "rejected_sample": 1}
    assert "above the maximum 100" in str(c.status.last_error)
    assert c.status.state == "listening"


async def test_a_stopped_connector_frees_its_port_and_its_device(platform: Platform) -> None:
    c = await platform.connector(format="json")
    assert c.address is not None
    assert platform.device.id in platform.services.device_hub.sessions
    await c.stop()
    assert c.status.state == "stopped"
    assert platform.device.id not in platform.services.device_hub.sessions
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as again:
        again.bind(c.address)  # free at once


async def test_a_port_in_use_is_a_clear_error(platform: Platform) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("127.0.0.1", 0))
        port = taken.getsockname()[1]
        with pytest.raises(ConnectorError) as caught:
            await platform.connector(format="json", port=port)
    assert str(caught.value) == (
        f"cannot listen for UDP on 127.0.0.1:{port}: Address already in use "
        "(another program or connector has it)"
    )
