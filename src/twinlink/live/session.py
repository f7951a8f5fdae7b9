"""One live connection's state: who the caller is, its subscriptions, its answers.

The session knows nothing of WebSockets: it reads client frames (`handle`), keeps the hub
informed, and puts every answer in the connection's `Outbox`. Its methods run one at a time
(the connection's reader and its periodic check take turns), so the subscriptions change in
one place only; `command` ops are started there and run beside it (`CommandOps`).
"""

from __future__ import annotations

import logging
from typing import Any, Protocol

from twinlink.auth.rights import Principal
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.records import TwinRecord
from twinlink.live import protocol
from twinlink.live.commands import CommandOps, CommandSender
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.protocol import CommandRequest, LiveMessageError, SubscribeRequest
from twinlink.live.subscription import Subscription

log = logging.getLogger("twinlink.live")


class Authenticator(Protocol):
    async def authenticate(self, token: str) -> Principal: ...


class TwinFinder(Protocol):
    async def require_role(
        self, principal: Principal, slug: str, needed: str, what: str
    ) -> TwinRecord: ...


class LatestReader(Protocol):
    async def __call__(
        self, twin_id: int, stream: str, signals: frozenset[str] | None
    ) -> dict[str, dict[str, Any]]: ...


async def no_latest(
    twin_id: int, stream: str, signals: frozenset[str] | None
) -> dict[str, dict[str, Any]]:
    return {}


class LiveSession:
    def __init__(
        self,
        token: str,
        principal: Principal,
        *,
        hub: LiveHub,
        outbox: Outbox,
        auth: Authenticator,
        registry: TwinFinder,
        latest: LatestReader = no_latest,
        commands: CommandSender | None = None,
    ) -> None:
        self.token = token
        self.principal = principal
        self.hub = hub
        self.outbox = outbox
        self.auth = auth
        self.registry = registry
        self.latest = latest
        self.subs: dict[str, Subscription] = {}
        self.commands = None if commands is None else CommandOps(commands, outbox)

    async def handle(self, raw: str | bytes) -> None:
        """Act on one client frame. A token found invalid raises AuthError (close 4401);
        anything else wrong with the frame is answered with an `error` message."""
        try:
            await self._dispatch(protocol.read_message(raw))
        except LiveMessageError as err:
            self.outbox.put_control(protocol.error(err))

    async def _dispatch(self, message: dict[str, Any]) -> None:
        op = message["op"]
        if op == "subscribe":
            await self.subscribe(protocol.read_subscribe(message))
        elif op == "unsubscribe":
            self.unsubscribe(protocol.read_sub_id(message))
        elif op == "command":
            await self.command(protocol.read_command(message))
        elif op == "ping":
            self.outbox.put_control(protocol.pong(message))
        elif op == "auth":
            raise LiveMessageError("already authenticated", op="auth")
        else:
            shown = op if len(op) <= 40 else op[:37] + "..."
            raise LiveMessageError(
                f"unknown op {shown!r}; expected one of {', '.join(protocol.OPS)}", op=shown
            )

    async def subscribe(self, request: SubscribeRequest) -> None:
        if request.id in self.subs:
            raise LiveMessageError(
                f"subscription {request.id!r} exists; unsubscribe it first", "subscribe", request.id
            )
        if len(self.subs) >= protocol.MAX_SUBSCRIPTIONS:
            raise LiveMessageError(
                f"a connection holds at most {protocol.MAX_SUBSCRIPTIONS} subscriptions",
                "subscribe",
                request.id,
            )
        # Each subscribe checks the token again, so a revoked one is noticed at once.
        self.principal = await self.auth.authenticate(self.token)
        try:
            twin = await self.registry.require_role(
                self.principal, request.twin, "viewer", "the live streams"
            )
        except (NotFoundError, ForbiddenError) as err:
            raise LiveMessageError(str(err), "subscribe", request.id) from err
        sub = Subscription(
            request.id, twin.id, twin.slug, request.stream, request.signals, request.max_rate
        )
        self.subs[sub.id] = sub
        # Live delivery starts before `latest` is read: a batch published meanwhile may be in
        # both, none is in neither. Its samples wait in the outbox until `subscribed` is sent.
        self.hub.add(sub, self.outbox)
        try:
            latest = await self.latest(sub.twin_id, sub.stream, sub.signals)
        except Exception:
            log.exception("reading latest values failed", extra={"event": "live_latest"})
            latest = {}
        self.outbox.put_control(protocol.subscribed(sub, latest))
        sub.started = True

    async def command(self, request: CommandRequest) -> None:
        if self.commands is None:
            raise LiveMessageError("commands are not available here", "command", request.id)
        # Each command checks the token again (a cached answer: see AuthService), so a revoked
        # one is noticed at once; the rights on the twin are CommandService's to check.
        self.principal = await self.auth.authenticate(self.token)
        await self.commands.start(self.principal, request)

    def unsubscribe(self, sub_id: str) -> None:
        sub = self.subs.get(sub_id)
        if sub is None:
            raise LiveMessageError(f"no subscription {sub_id!r}", "unsubscribe", sub_id)
        self._end(sub)
        self.outbox.put_control(protocol.unsubscribed(sub_id))

    async def recheck(self) -> None:
        """Check the token again (AuthError when it is no longer valid), and end each
        subscription whose twin the caller may no longer see (or that was deleted)."""
        self.principal = await self.auth.authenticate(self.token)
        for sub in list(self.subs.values()):
            reason = f"no twin {sub.twin!r}"
            try:
                twin = await self.registry.require_role(
                    self.principal, sub.twin, "viewer", "the live streams"
                )
            except (NotFoundError, ForbiddenError) as err:
                reason = str(err)
            else:
                if twin.id == sub.twin_id:
                    continue
            self._end(sub)
            self.outbox.put_control(protocol.unsubscribed(sub.id, reason))

    def _end(self, sub: Subscription) -> None:
        del self.subs[sub.id]
        self.hub.remove(sub)
        self.outbox.forget(sub)

    def close(self) -> None:
        """The connection ended: leave the hub (the last watcher of a stream ends its bus
        subscription). `stop_commands` ends the command ops."""
        for sub in list(self.subs.values()):
            self._end(sub)

    async def stop_commands(self) -> None:
        if self.commands is not None:
            await self.commands.close()
