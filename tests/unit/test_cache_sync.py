"""CacheSync (cluster.py): a change on one node empties the caches of the others, through the
bus; two nodes share one MemoryBus here (the KafkaBus between two real `twinlink up` nodes:
tests/integration/test_scale_out_nodes.py)."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, cast

import pytest

from twinlink.auth.service import AuthService
from twinlink.bus import MemoryBus
from twinlink.cluster import SUBJECT, CacheSync
from twinlink.gateway.service import GatewayService
from twinlink.registry.service import RegistryService


@dataclass
class Counted:
    """What CacheSync uses of the registry, the auth service and the gateway service."""

    generation: int = 0
    forgotten: int = 0
    changed_listeners: list[Callable[[], None]] = field(default_factory=list)

    def changed(self) -> None:  # as the services' own: bump, then tell the listeners
        self.generation += 1
        for listener in self.changed_listeners:
            listener()

    def forget_cached(self) -> None:
        self.generation += 1
        self.forgotten += 1


@dataclass
class Node:
    registry: Counted
    auth: Counted
    gateway: Counted
    sync: CacheSync


def node(bus: MemoryBus) -> Node:
    registry, auth, gateway = Counted(), Counted(), Counted()
    sync = CacheSync(
        bus,
        cast(RegistryService, registry),
        cast(AuthService, auth),
        cast(GatewayService, gateway),
    )
    sync.start()
    return Node(registry, auth, gateway, sync)


async def settled(*nodes: Node) -> None:
    """Until every node has sent what it had to send (its sender task is done)."""
    for n in nodes:
        if n.sync._sender is not None:
            await n.sync._sender


async def test_a_change_on_one_node_empties_the_caches_of_the_other_not_its_own_twice() -> None:
    bus = MemoryBus()
    a, b = node(bus), node(bus)
    a.registry.changed()
    await settled(a, b)
    assert (a.registry.generation, b.registry.generation) == (1, 1)  # A's own message skipped
    a.auth.changed()
    a.gateway.changed()
    await settled(a, b)
    assert (b.auth.forgotten, b.auth.generation, b.gateway.generation) == (1, 1, 1)
    assert (a.auth.forgotten, b.registry.generation) == (0, 1)
    await a.sync.stop()
    await b.sync.stop()


async def test_what_the_other_node_hears_does_not_go_back_to_the_first() -> None:
    bus = MemoryBus()
    seen: list[Any] = []
    bus.subscribe(SUBJECT, lambda subject, message: seen.append(message))
    a, b = node(bus), node(bus)
    a.registry.changed()
    await settled(a, b)
    assert [m["node"] for m in seen] == [a.sync.node]  # B bumped, and said nothing
    await a.sync.stop()
    await b.sync.stop()


async def test_changes_in_a_row_go_out_as_one_message() -> None:
    bus = MemoryBus()
    seen: list[Any] = []
    bus.subscribe(SUBJECT, lambda subject, message: seen.append(message))
    a = node(bus)
    for _ in range(5):
        a.registry.changed()
    a.auth.changed()
    await settled(a)
    assert [m["what"] for m in seen] == [["auth", "registry"]]
    await a.sync.stop()


async def test_stop_sends_what_changed_and_then_listens_no_more() -> None:
    bus = MemoryBus()
    a, b = node(bus), node(bus)
    a.gateway.changed()
    await a.sync.stop()  # before its sender ran: the change still goes out
    assert b.gateway.generation == 1
    await b.sync.stop()
    a.gateway.changed()  # nobody listens any more: no task made, nothing sent
    assert a.sync._sender is not None and a.sync._sender.done()
    assert (a.gateway.changed_listeners, b.gateway.generation) == ([], 1)


async def test_a_message_the_bus_refuses_is_logged_and_the_next_change_still_sent(
    caplog: pytest.LogCaptureFixture,
) -> None:
    bus = MemoryBus()
    a, b = node(bus), node(bus)
    real_publish = bus.publish
    refused = [True]

    async def publish(subject: str, message: object) -> None:
        if refused.pop():
            raise ConnectionError("the broker is away")
        await real_publish(subject, message)

    bus.publish = publish  # type: ignore[method-assign]
    a.registry.changed()
    await settled(a)
    assert b.registry.generation == 0
    assert [r.event for r in caplog.records if r.levelno == logging.WARNING] == [  # type: ignore[attr-defined]
        "cache_sync_failed"
    ]
    refused.append(False)
    a.registry.changed()
    await settled(a)
    assert b.registry.generation == 1
    await a.sync.stop()
    await b.sync.stop()


def test_messages_not_of_cache_sync_are_ignored() -> None:
    bus = MemoryBus()
    b = node(bus)
    for message in (None, "x", {"node": "other"}, {"node": "other", "what": "registry"}):
        bus.publish_now(SUBJECT, message)
    bus.publish_now(SUBJECT, {"node": "other", "what": ["registry", "unknown"]})
    assert (b.registry.generation, b.auth.generation, b.gateway.generation) == (1, 0, 0)
