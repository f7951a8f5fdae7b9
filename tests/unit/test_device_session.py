"""A device session's message order: the welcome is always first."""

from __future__ import annotations

import asyncio

import orjson

from twinlink.domain.records import Device
from twinlink.ingest.sessions import DeviceSession


class Wire:
    def __init__(self) -> None:
        self.sent: asyncio.Queue[dict[str, object]] = asyncio.Queue()

    async def send_text(self, data: str) -> None:
        await self.sent.put(orjson.loads(data))

    async def close(self, code: int, reason: str) -> None:
        return None


def device() -> Device:
    return Device(1, 1, "rig-twin", "rig", "", "tld_x", 0, None)


async def test_messages_sent_before_the_welcome_follow_it_in_order() -> None:
    wire = Wire()
    session = DeviceSession(device(), wire)
    assert session.send({"type": "command", "id": "a"})
    assert session.send({"type": "command", "id": "b"})
    session.open({"type": "welcome"})
    session.send({"type": "command", "id": "c"})
    got = [await wire.sent.get() for _ in range(4)]
    await session.close()
    assert [m.get("id", m["type"]) for m in got] == ["welcome", "a", "b", "c"]


async def test_a_closed_session_refuses_messages() -> None:
    session = DeviceSession(device(), Wire())
    session.open({"type": "welcome"})
    await session.close()
    assert session.send({"type": "command", "id": "a"}) is False
