"""Commands across nodes (commands/relay.py): command services of several "nodes" on one store
and one bus, each with its own device hub, the device's session on one of them. The bus is the
memory bus here; tests/integration/test_scale_out_commands.py runs the same over Kafka."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass
from typing import Any

import orjson
import pytest

from tests.unit._services import SLUG, Setting, setting
from tests.unit._storage import Stores
from tests.unit._storage import stores as stores  # fixture
from twinlink.bus import MemoryBus
from twinlink.commands import CommandService
from twinlink.commands import relay as relay_module
from twinlink.ingest.sessions import DeviceSession

DEADLINE_S = 10.0


class Wire:
    """What a device's session put on the wire."""

    def __init__(self) -> None:
        self.sent: list[dict[str, Any]] = []

    async def send_text(self, data: str) -> None:
        self.sent.append(orjson.loads(data))

    async def close(self, code: int, reason: str) -> None:
        return None

    def commands(self) -> list[str]:
        return [m["id"] for m in self.sent if m.get("type") == "command"]


@dataclass
class Node:
    world: Setting
    commands: CommandService


async def until(check: Callable[[], object], what: str) -> None:
    """Let the loop run the bus's tasks until `check()` holds (AssertionError after
    DEADLINE_S)."""
    deadline = asyncio.get_running_loop().time() + DEADLINE_S
    while not check():
        if asyncio.get_running_loop().time() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        await asyncio.sleep(0.001)


@pytest.fixture
async def cluster(stores: Stores) -> AsyncIterator[Callable[[], Any]]:
    """Starts nodes on one store and one bus; all are closed at the end."""
    bus, first, nodes = MemoryBus(), await setting(stores), []

    async def start() -> Node:
        world = first if not nodes else first.fresh()
        node = Node(world, CommandService(world.registry, stores.commands, world.hub, 30.0, bus))
        await node.commands.open()
        nodes.append(node)
        return node

    yield start
    for node in nodes:
        await node.commands.close()


async def connect(node: Node) -> tuple[DeviceSession, Wire]:
    """The device connects to `node`, as the device WebSocket does it."""
    wire = Wire()
    session = DeviceSession(node.world.device, wire)
    await node.world.hub.attach(session)
    session.open({"type": "welcome"})
    await node.world.hub.connected(session)
    return session, wire


async def answer(node: Node, session: DeviceSession, message: dict[str, Any]) -> None:
    """The device's message, handled by the node its session is on."""
    await node.world.hub.handlers[message["type"]](session, message)


async def test_a_command_sent_on_a_goes_to_the_device_on_b_and_its_result_comes_back(
    cluster: Callable[[], Any],
) -> None:
    a, b = await cluster(), await cluster()
    session, wire = await connect(b)
    sending = asyncio.create_task(a.commands.send(a.world.owner, SLUG, "pause", {"n": 1}))
    await until(wire.commands, "the command on B's session")
    [command_id] = wire.commands()
    await answer(b, session, {"type": "delivered", "id": command_id})
    await until(lambda: a.commands._live[command_id].record.state == "delivered", "delivered")
    await answer(b, session, {"type": "result", "id": command_id, "status": "succeeded",
                              "result": {"ok": True}})  # fmt: skip
    record = await sending
    assert (record.id, record.state, record.result) == (command_id, "succeeded", {"ok": True})
    assert record.delivered_ns is not None and record.finished_ns is not None
    await session.close()


async def test_a_device_no_node_holds_is_offline(
    cluster: Callable[[], Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(relay_module, "PUSH_WAIT_S", 0.05)  # no node will answer
    a, _ = await cluster(), await cluster()
    record = await a.commands.send(a.world.owner, SLUG, "pause")
    assert (record.state, record.error) == ("failed", "device offline")


async def test_a_queued_command_held_by_several_nodes_is_sent_once(
    cluster: Callable[[], Any],
) -> None:
    a = await cluster()
    queued = await a.commands.send(a.world.owner, SLUG, "pause", queue=True, wait=False)
    # Nodes started now take the open command up from the store, as after a restart.
    b, c = await cluster(), await cluster()
    taken: list[object] = []
    assert a.commands.relay is not None
    a.commands.relay.bus.subscribe(
        "command-results.*", lambda _, m: taken.append(m) if m["type"] == "taken" else None
    )
    session, wire = await connect(b)
    # B sends it (it took the command up too), then A and C push it to B: B answers each
    # `taken`, and sends it no second time.
    await until(lambda: len(taken) == 2, "A's and C's pushes answered")
    assert wire.commands() == [queued.id]
    await answer(b, session, {"type": "result", "id": queued.id, "status": "succeeded"})
    # Every node that tracked it lets it go finished: none expires it later over the result.
    for node in (a, b, c):
        await until(lambda n=node: queued.id not in n.commands._live, "the command finished")
    stored = await a.commands.get(a.world.owner, SLUG, queued.id)
    assert stored.state == "succeeded"
    await session.close()


async def test_a_result_for_a_command_the_node_never_sent_is_refused(
    cluster: Callable[[], Any],
) -> None:
    a, b = await cluster(), await cluster()
    session, _ = await connect(b)
    with pytest.raises(ValueError, match="no command 'nope'"):
        await answer(b, session, {"type": "result", "id": "nope", "status": "succeeded"})
    assert a.commands._live == {}
    await session.close()


async def test_without_a_shared_bus_there_is_no_relay(stores: Stores) -> None:
    world = await setting(stores)
    service = CommandService(world.registry, stores.commands, world.hub, 30.0)
    assert service.relay is None


async def test_a_device_polling_b_takes_a_command_sent_on_a(cluster: Callable[[], Any]) -> None:
    a, b = await cluster(), await cluster()
    polling = asyncio.create_task(b.commands.poll(b.world.device, 10.0))
    await until(lambda: b.commands._polls, "the poll waiting on B")
    sending = asyncio.create_task(a.commands.send(a.world.owner, SLUG, "pause", {"n": 2}))
    [polled] = await polling
    assert (polled.name, polled.args, polled.state) == ("pause", {"n": 2}, "delivered")
    await until(lambda: a.commands._live[polled.id].record.state == "delivered", "delivered")
    done = await b.commands.record_result(b.world.device, polled.id, "failed", None, "jammed")
    assert done.state == "failed"
    record = await sending
    assert (record.id, record.state, record.error) == (polled.id, "failed", "jammed")
    assert await b.commands.poll(b.world.device, 0) == []  # delivered once
