"""Sending commands to devices and waiting for their results.

The state of every open command (pending or delivered) is held in memory: a future its sender
may wait on and a timer that expires it. Each change of state is written to the command log
behind the caller (`WriteBehind`), so the round trip never waits for a disk; the exception is
a command sent with `queue`, which is durable before `send` returns. Open commands are loaded
again when the server starts.

A device is online while it has a WebSocket session or an HTTP long poll is waiting. Offline,
a command without `queue` fails at once ("device offline"); with `queue` it is sent when the
device connects (or polls), until it expires. Which device a command goes to when it names
none: `targets.py`. On a shared bus (several nodes), `relay.py` hands a command to the node
holding its device, and brings back what the device answers.
"""

from __future__ import annotations

import asyncio
import time
from collections import defaultdict
from dataclasses import dataclass
from typing import Any

from twinlink.auth.rights import Principal, has_role
from twinlink.bus import Bus
from twinlink.commands.interfaces import InterfaceRules
from twinlink.commands.relay import CommandRelay
from twinlink.commands.rules import check_command
from twinlink.commands.targets import DeviceTargets
from twinlink.commands.write_behind import WriteBehind
from twinlink.domain.commands import OFFLINE, STATES, CommandRecord, new_command_id
from twinlink.domain.errors import ForbiddenError, InvalidInputError, NotFoundError
from twinlink.domain.records import Device, TwinRecord
from twinlink.ingest.sessions import DeviceHub, DeviceSession
from twinlink.registry.service import RegistryService
from twinlink.store.commands import CommandStore

MAX_TIMEOUT_S = 7 * 24 * 3600.0
MAX_ERROR_CHARS = 4096
MAX_LIST = 1000


@dataclass(slots=True)
class _Live:
    record: CommandRecord
    done: asyncio.Future[None]
    timer: asyncio.TimerHandle


class CommandService:
    def __init__(
        self,
        registry: RegistryService,
        store: CommandStore,
        hub: DeviceHub,
        default_timeout_s: float,
        shared_bus: Bus | None = None,
    ) -> None:
        """`shared_bus`: the bus other nodes share (Kafka), over which commands reach their
        devices' nodes; None on one node (embedded), where nothing of that runs."""
        self.registry = registry
        self.hub = hub
        self.store = store
        self.default_timeout_s = default_timeout_s
        self.log = WriteBehind(store.save_commands)
        self.rules = InterfaceRules(registry)
        self.targets = DeviceTargets(registry, self._online)
        self._live: dict[str, _Live] = {}
        self._by_device: defaultdict[int, dict[str, _Live]] = defaultdict(dict)
        self._polls: defaultdict[int, set[asyncio.Future[None]]] = defaultdict(set)
        self._tasks: set[asyncio.Task[None]] = set()
        hub.handle("delivered", self._on_delivered)
        hub.handle("result", self._on_result)
        hub.on_connect(self._on_connect)
        registry.deleted_listeners.append(self._twins_deleted)
        self.relay: CommandRelay | None = None
        if shared_bus is not None:
            self.relay = CommandRelay(
                shared_bus, hub, self._remote_event, self._queued_for, self._wake_polls
            )

    async def open(self) -> None:
        """Take up the commands a previous run left open (the store is open)."""
        now = time.time_ns()
        for record in await self.store.open_commands():
            if record.expires_ns <= now:  # expired while the server was down
                record.expire(record.expires_ns)
                self.log.save(record)
            else:
                self._track(record)
        if self.relay is not None:
            self.relay.start()

    async def close(self) -> None:
        """Stop the timers and write what is unsaved; open commands stay open in the log."""
        for live in self._live.values():
            live.timer.cancel()
        if self.relay is not None:
            await self.relay.stop()
        if self._tasks:
            await asyncio.gather(*self._tasks, return_exceptions=True)
        await self.log.close()  # best effort: a full disk does not fail the shutdown

    # -- people ----------------------------------------------------------------------------

    async def send(
        self,
        principal: Principal,
        slug: str,
        name: str,
        args: dict[str, Any] | None = None,
        device: str | None = None,
        timeout_s: float | None = None,
        queue: bool = False,
        wait: bool = True,
    ) -> CommandRecord:
        """Send a command; with `wait`, return once it succeeded, failed or expired."""
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "editor"):
            raise ForbiddenError(
                f"a viewer cannot send commands; sending to {slug!r} needs the editor role"
            )
        timeout = self.default_timeout_s if timeout_s is None else timeout_s
        if not 0 < timeout <= MAX_TIMEOUT_S:
            raise InvalidInputError(f"`timeout_s` must be above 0 and at most {MAX_TIMEOUT_S:.0f}")
        target = await self.targets.target(twin, device)
        checked = check_command(await self.rules.get(twin.id), name, args)
        now = time.time_ns()
        record = CommandRecord(
            id=new_command_id(), twin_id=twin.id, device_id=target.id, device=target.name,
            name=name, args=checked, state="pending", queued=queue,
            sent_by=principal.user.username if principal.user else None,
            created_ns=now, expires_ns=now + int(timeout * 1e9),
        )  # fmt: skip
        live = self._track(record)
        self.log.save(record)
        pushed = self._push(record)
        if not pushed and self.relay is not None:  # the device may be on another node
            # A queued command waits for no answer: it stays pending either way.
            pushed = await self.relay.push(record, wait=not queue)
        if not pushed and not queue:
            self._settle(live, record.fail(OFFLINE, now))
            return record
        if queue:
            await self.log.sync()  # a queued command survives a restart
        if wait:
            # Only this call waits on `done`: a caller that goes away (cancelled) cancels it,
            # which stops nothing; the command goes on and `_settle` skips a done future.
            await live.done
        return record

    async def list_commands(
        self,
        principal: Principal,
        slug: str,
        state: str | None = None,
        name: str | None = None,
        device: str | None = None,
        limit: int = 100,
    ) -> list[CommandRecord]:
        """The twin's command log, newest first (viewers)."""
        twin = await self._twin_for_reading(principal, slug)
        if state is not None and state not in STATES:
            raise InvalidInputError(f"`state` must be one of {', '.join(STATES)}")
        await self.log.sync()
        return await self.store.list_commands(twin.id, state, name, device, min(limit, MAX_LIST))

    async def get(self, principal: Principal, slug: str, command_id: str) -> CommandRecord:
        twin = await self._twin_for_reading(principal, slug)
        record = await self._find(command_id)
        if record is None or record.twin_id != twin.id:
            raise NotFoundError(f"twin {slug!r} has no command {command_id!r}")
        return record

    async def _twin_for_reading(self, principal: Principal, slug: str) -> TwinRecord:
        """A twin's data needs a role on it: seeing its public document is not enough."""
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "viewer"):
            raise ForbiddenError(f"the commands of {slug!r} need the viewer role")
        return twin

    async def default_device(self, principal: Principal, slug: str) -> str | None:
        """The device a command to the twin goes to now when it names none (viewers); None
        when the sender has to name one."""
        return await self.targets.chosen(await self._twin_for_reading(principal, slug))

    async def _find(self, command_id: str) -> CommandRecord | None:
        live = self._live.get(command_id)
        if live is not None:
            return live.record
        await self.log.sync()  # a command that just finished may not be committed yet
        return await self.store.get_command(command_id)

    # -- devices ---------------------------------------------------------------------------

    async def record_result(
        self, device: Device, command_id: str, status: str, result: Any, error: str | None
    ) -> CommandRecord:
        """A device's result; NotFoundError when the command is not this device's."""
        if isinstance(error, str) and len(error) > MAX_ERROR_CHARS:
            error = error[: MAX_ERROR_CHARS - 3] + "..."
        now = time.time_ns()
        if self.relay is not None:  # polled here for another node, which records it
            message = _result_message(command_id, status, result, error)
            relayed = self.relay.finish_polled(device, message)
            if relayed is not None:
                return relayed
        live = self._live.get(command_id)
        if live is not None and live.record.device_id == device.id:
            self._settle(live, live.record.finish(status, result, error, now))
            if self.relay is not None:  # for the other nodes tracking it
                self.relay.announce(device, _result_message(command_id, status, result, error))
            return live.record
        record = await self._find(command_id)
        if record is None or record.device_id != device.id:
            raise NotFoundError(f"this device has no command {command_id!r}")
        if record.finish(status, result, error, now):  # a late result for an expired command
            self.log.save(record)
        return record

    async def poll(self, device: Device, wait_s: float) -> list[CommandRecord]:
        """The device's pending commands, waiting up to `wait_s` for one; they are delivered
        by this answer (the HTTP long poll)."""
        if self.relay is not None:  # the queued commands other nodes hold for it
            self.relay.connected(device)
        found = self._pending(device.id)
        if not found and wait_s > 0:
            waiter: asyncio.Future[None] = asyncio.get_running_loop().create_future()
            self._polls[device.id].add(waiter)
            try:
                await asyncio.wait([waiter], timeout=wait_s)
            finally:
                self._polls[device.id].discard(waiter)
                if not self._polls[device.id]:
                    del self._polls[device.id]
            found = self._pending(device.id)
        now = time.time_ns()
        for record in found:
            if not record.deliver(now):
                continue
            if self.relay is None or not self.relay.delivered_polled(device, record):
                self.log.save(record)
        return found

    def _pending(self, device_id: int) -> list[CommandRecord]:
        lives = self._by_device.get(device_id, {}).values()
        found = [live.record for live in lives if live.record.state == "pending"]
        if self.relay is not None:
            found += self.relay.pending_polled(device_id)
        return found

    async def _on_delivered(
        self, session: DeviceSession, message: dict[str, Any]
    ) -> dict[str, Any] | None:
        live = self._live.get(_command_id(message))
        # Ids that are not open (already finished, expired, someone else's) are ignored.
        if (
            live is not None
            and live.record.device_id == session.device.id
            and live.record.deliver(time.time_ns())
        ):
            self.log.save(live.record)
        if self.relay is not None and (
            live is not None or self.relay.holds(_command_id(message), session.device)
        ):
            self.relay.announce(session.device, message)  # the node that sent it tracks it
        return None

    async def _on_result(
        self, session: DeviceSession, message: dict[str, Any]
    ) -> dict[str, Any] | None:
        status, result, error = read_result(message)
        command_id = _command_id(message)
        if (
            self.relay is not None
            and command_id not in self._live
            and self.relay.holds(command_id, session.device)
        ):  # sent here for another node, which tracks it
            self.relay.announce(session.device, _result_message(command_id, status, result, error))
            return None
        try:
            await self.record_result(session.device, _command_id(message), status, result, error)
        except NotFoundError as err:
            raise ValueError(str(err)) from err
        return None

    async def _on_connect(self, session: DeviceSession) -> None:
        """Send the queued commands still pending; the device answers `delivered` (and may
        see a command again after a reconnect: ids make that harmless)."""
        device = session.device
        for live in list(self._by_device.get(device.id, {}).values()):
            record = live.record
            # created_ns: not a command for a deleted device whose id was given to this one
            if (
                record.queued
                and record.state == "pending"
                and record.created_ns >= device.created_ns
            ):
                session.send(record.message())
                if self.relay is not None:
                    self.relay.sent(record, session)
        if self.relay is not None:  # the queued commands other nodes hold for it
            self.relay.connected(device)

    # -- other nodes (a shared bus) --------------------------------------------------------

    def _remote_event(self, message: dict[str, Any]) -> None:
        """What a device answered on another node, for a command this node tracks."""
        live = self._live.get(str(message.get("id")))
        if live is None or live.record.device_id != message.get("device"):
            return
        now = time.time_ns()
        if message.get("type") == "delivered":
            if live.record.deliver(now):
                self.log.save(live.record)
        elif message.get("type") == "result":
            try:
                status, result, error = read_result(message)
                self._settle(live, live.record.finish(status, result, error, now))
            except ValueError:  # checked by the node it came to; not from a twinlink node
                return

    def _queued_for(self, device_id: int, device_created_ns: int) -> list[CommandRecord]:
        return [
            live.record
            for live in self._by_device.get(device_id, {}).values()
            if live.record.queued
            and live.record.state == "pending"
            and live.record.created_ns >= device_created_ns
        ]

    # -- state -----------------------------------------------------------------------------

    def _track(self, record: CommandRecord) -> _Live:
        loop = asyncio.get_running_loop()
        delay = max(0.0, (record.expires_ns - time.time_ns()) / 1e9)
        timer = loop.call_later(delay, self._expire, record.id)
        live = _Live(record, loop.create_future(), timer)
        self._live[record.id] = live
        self._by_device[record.device_id][record.id] = live
        return live

    def _online(self, device_id: int) -> bool:
        return self.hub.session(device_id) is not None or bool(self._polls.get(device_id))

    def _push(self, record: CommandRecord) -> bool:
        """Send to the device now; False when it is offline."""
        session = self.hub.session(record.device_id)
        if session is not None and session.send(record.message()):
            return True
        return self._wake_polls(record.device_id)

    def _wake_polls(self, device_id: int) -> bool:
        """Wake the device's waiting HTTP polls; False when none waits."""
        waiters = self._polls.get(device_id)
        if not waiters:
            return False
        for waiter in waiters:
            if not waiter.done():
                waiter.set_result(None)
        return True

    def _expire(self, command_id: str) -> None:
        live = self._live.get(command_id)
        if live is not None:
            self._settle(live, live.record.expire(time.time_ns()))

    def _settle(self, live: _Live, changed: bool) -> None:
        """After a transition: save it, and when the command is finished let it go."""
        if not changed:
            return
        self.log.save(live.record)
        if live.record.is_open:
            return
        live.timer.cancel()
        self._live.pop(live.record.id, None)
        lives = self._by_device.get(live.record.device_id)
        if lives is not None:
            lives.pop(live.record.id, None)
            if not lives:
                del self._by_device[live.record.device_id]
        if not live.done.done():
            live.done.set_result(None)

    def _twins_deleted(self, twin_ids: list[int]) -> None:
        doomed = set(twin_ids)
        now = time.time_ns()
        for live in [x for x in self._live.values() if x.record.twin_id in doomed]:
            self._settle(live, live.record.fail("the twin was deleted", now))
        task = asyncio.create_task(self._forget(twin_ids))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _forget(self, twin_ids: list[int]) -> None:
        await self.log.sync()  # so no late upsert brings a deleted command back
        await self.store.delete_commands_of(twin_ids)


def _command_id(message: dict[str, Any]) -> str:
    command_id = message.get("id")
    if not isinstance(command_id, str) or not command_id:
        raise ValueError("`id` must be the command's id (a string)")
    return command_id


def _result_message(command_id: str, status: str, result: Any, error: str | None) -> dict[str, Any]:
    return {"type": "result", "id": command_id, "status": status, "result": result, "error": error}


def read_result(body: dict[str, Any]) -> tuple[str, Any, str | None]:
    """`status`, `result` and `error` of a device's result; ValueError when unusable."""
    status = body.get("status")
    if status not in ("succeeded", "failed"):
        raise ValueError("`status` must be succeeded or failed")
    error = body.get("error")
    if error is not None and not isinstance(error, str):
        raise ValueError("`error` must be a string")
    return status, body.get("result"), error
