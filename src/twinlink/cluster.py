"""Node-local caches kept right when several nodes share one store (docs/scale-out.md).

Each node caches what it read from the metadata store: twins by slug and roles (the registry's
generation, which ingest's interface rules, the devices commands go to and the gateway's
services follow too), tokens with their users (AuthService), the gateway's services. A change
made on a node empties that node's caches as it always did; `CacheSync` then tells the other
nodes over the bus (subject `caches.changed`, which names the node and what changed), and
empties theirs when they tell it. A node's own messages come back to it and are skipped.

Sent after the change is committed, so a node that hears of it and reads again reads the new
value; a read that was underway when the message came is not cached (GenerationCache).
Changes in a row go out as one message. When the bus refuses the message (Kafka down), the
other nodes are not told: that is logged, and their caches of tokens still end within
TOKEN_CACHE_S, the others at their own next change.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
from collections.abc import Callable

from twinlink.auth.service import TOKEN_CACHE_S, AuthService
from twinlink.bus import Bus
from twinlink.bus.base import Unsubscribe
from twinlink.gateway.service import GatewayService
from twinlink.registry.service import RegistryService

log = logging.getLogger("twinlink.cluster")

SUBJECT = "caches.changed"


class CacheSync:
    def __init__(
        self, bus: Bus, registry: RegistryService, auth: AuthService, gateway: GatewayService
    ) -> None:
        self.bus = bus
        self.node = secrets.token_hex(8)  # tells this node's own messages from the others'
        self.registry, self.auth, self.gateway = registry, auth, gateway
        self._pending: set[str] = set()
        self._sender: asyncio.Task[None] | None = None
        self._unsubscribe: Unsubscribe | None = None
        self._listeners: list[tuple[list[Callable[[], None]], Callable[[], None]]] = [
            (registry.changed_listeners, lambda: self._changed("registry")),
            (auth.changed_listeners, lambda: self._changed("auth")),
            (gateway.changed_listeners, lambda: self._changed("gateway")),
        ]

    def start(self) -> None:
        """After the bus has started."""
        self._unsubscribe = self.bus.subscribe(SUBJECT, self._heard)
        for listeners, listener in self._listeners:
            listeners.append(listener)

    async def stop(self) -> None:
        """Before the bus stops: what changed here until now is still sent."""
        for listeners, listener in self._listeners:
            if listener in listeners:
                listeners.remove(listener)
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        if self._sender is not None:
            await self._sender

    def _changed(self, what: str) -> None:
        self._pending.add(what)
        if self._sender is None or self._sender.done():
            self._sender = asyncio.get_running_loop().create_task(self._send())

    async def _send(self) -> None:
        while self._pending:  # what changed while a message was being sent goes in the next
            what = sorted(self._pending)
            self._pending.clear()
            try:
                await self.bus.publish(SUBJECT, {"node": self.node, "what": what})
            except Exception as err:
                log.warning(
                    "the other nodes were not told of a change: they may answer from their "
                    f"caches (tokens for up to {TOKEN_CACHE_S:.0f} s, twins and roles until "
                    "their next change)",
                    extra={"event": "cache_sync_failed", "what": what, "error": str(err)},
                )

    def _heard(self, subject: str, message: object) -> None:
        if not isinstance(message, dict) or message.get("node") == self.node:
            return
        what = message.get("what")
        if not isinstance(what, list):
            return
        # Bumped here, not through changed(): that would tell the other nodes again.
        if "registry" in what:
            self.registry.generation += 1
        if "auth" in what:
            self.auth.forget_cached()
        if "gateway" in what:
            self.gateway.generation += 1
