"""Commands across nodes, on a shared bus (TWINLINK_BUS_URL; docs/scale-out.md).

A device's session is on the node it connected to; a command is sent, tracked (its future,
its timer) and saved by the node it was posted to. When that node does not hold the device,
it publishes the command on `commands.{twin_id}` ("push"); the node holding the device's
session sends it and answers "taken" on `command-results.{twin_id}`. The sender waits up to
PUSH_WAIT_S for that answer, then counts the device as offline. What the device answers
(`delivered`, `result`) is published on `command-results.{twin_id}` by the node it answered
on, and every node tracking the command applies it, so the sender's caller gets its result
as for a local device, and a node that took the command up at its start does not later
expire what another node finished.

When a device connects, its node publishes "connected": every node holding queued commands
for it pushes them there. The node holding the session sends each command id once per
session, however many nodes push it, so with N nodes a command is delivered once.

A device that polls over HTTP instead: the node where its poll waits takes the pushed
command for it (a poll says "connected" too, so queued commands come), delivers it with the
poll's answer and tells the sender, and the result the device posts there goes to the sender
as a WebSocket's does.

The embedded default (the memory bus, one node) has no relay: nothing of this runs there.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from collections.abc import Callable
from dataclasses import asdict
from typing import Any

from twinlink.bus import Bus
from twinlink.bus.base import Unsubscribe
from twinlink.domain.commands import CommandRecord
from twinlink.domain.records import Device
from twinlink.ingest.sessions import DeviceHub, DeviceSession

log = logging.getLogger("twinlink.commands")

# How long the sender waits for the node holding the device to say it took a command (the
# bus between nodes takes milliseconds; a loaded machine far more), after which the device
# counts as offline.
PUSH_WAIT_S = 3.0
_PRUNE_AT = 10_000  # sent ids kept before the expired ones are dropped

# A node's device event (`delivered`, `result`) for a command it may track.
RemoteEvent = Callable[[dict[str, Any]], None]
# The queued, pending commands a node tracks for a device (id, created_ns).
QueuedFor = Callable[[int, int], list[CommandRecord]]
# Wakes a device's HTTP polls waiting on this node; False when none waits.
WakePolls = Callable[[int], bool]


class CommandRelay:
    def __init__(
        self,
        bus: Bus,
        hub: DeviceHub,
        on_event: RemoteEvent,
        queued_for: QueuedFor,
        wake_polls: WakePolls,
    ) -> None:
        self.bus, self.hub = bus, hub
        self.node = secrets.token_hex(8)
        self._on_event, self._queued_for, self._wake_polls = on_event, queued_for, wake_polls
        # Other nodes' commands taken by a device's HTTP poll here, until its result.
        self._polled: dict[str, CommandRecord] = {}
        self._taken: dict[str, asyncio.Future[None]] = {}
        # Ids this node sent to one of its sessions: (device id, session, expires_ns).
        self._sent: dict[str, tuple[int, DeviceSession, int]] = {}
        self._tasks: set[asyncio.Task[None]] = set()
        self._unsubscribe: list[Unsubscribe] = []

    def start(self) -> None:
        self._unsubscribe = [
            self.bus.subscribe("commands.*", self._heard_command),
            self.bus.subscribe("command-results.*", self._heard_result),
        ]

    async def stop(self) -> None:
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        self._unsubscribe = []
        if self._tasks:
            await asyncio.gather(*self._tasks, return_exceptions=True)

    # -- the sender's side --------------------------------------------------------------------

    async def push(self, record: CommandRecord, *, wait: bool) -> bool:
        """Hand `record` to the node holding its device; with `wait`, True once that node
        took it, False when none did within PUSH_WAIT_S (the device is offline)."""
        taken: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        if wait:
            self._taken[record.id] = taken
        try:
            await self.bus.publish(f"commands.{record.twin_id}", self._push_message(record))
            if not wait:
                return False
            async with asyncio.timeout(PUSH_WAIT_S):
                await taken
            return True
        except TimeoutError:
            return False
        except Exception as err:  # the bus refused it: as offline, said in the log
            log.warning(
                "a command could not be handed to the other nodes",
                extra={"event": "command_relay_failed", "command": record.id, "error": str(err)},
            )
            return False
        finally:
            self._taken.pop(record.id, None)

    def _push_message(self, record: CommandRecord) -> dict[str, Any]:
        return {
            "kind": "push", "node": self.node, "id": record.id, "device": record.device_id,
            "created_ns": record.created_ns, "expires_ns": record.expires_ns,
            "message": record.message(), "record": asdict(record),
        }  # fmt: skip

    # -- the device's node --------------------------------------------------------------------

    def sent(self, record: CommandRecord, session: DeviceSession) -> None:
        """`record` went to `session` on this node: a push of it is not sent again."""
        self._remember(record.id, session, record.expires_ns)

    def holds(self, command_id: str, device: Device) -> bool:
        """Whether this node sent command `command_id` to `device` for another node."""
        found = self._sent.get(command_id)
        return found is not None and found[0] == device.id

    def connected(self, device: Device) -> None:
        """`device` connected (or polls) here: the other nodes push its queued commands."""
        message = {"kind": "connected", "node": self.node, "device": device.id,
                   "created_ns": device.created_ns}  # fmt: skip
        self._publish(f"commands.{device.twin_id}", message)

    def announce(self, device: Device, message: dict[str, Any]) -> None:
        """A device's `delivered` or `result` message, for the nodes tracking the command."""
        event = {**message, "node": self.node, "device": device.id}
        if message.get("type") == "result":
            self._sent.pop(str(message.get("id")), None)
        self._publish(f"command-results.{device.twin_id}", event)

    # -- a device polling this node over HTTP -------------------------------------------------

    def pending_polled(self, device_id: int) -> list[CommandRecord]:
        """Other nodes' commands waiting for the device's next poll here."""
        polled = self._polled.values()
        return [r for r in polled if r.device_id == device_id and r.state == "pending"]

    def delivered_polled(self, device: Device, record: CommandRecord) -> bool:
        """A poll delivered `record`: True when it is another node's, which is told."""
        if self._polled.get(record.id) is not record:
            return False
        self.announce(device, {"type": "delivered", "id": record.id})
        return True

    def finish_polled(self, device: Device, result: dict[str, Any]) -> CommandRecord | None:
        """The device's result (a `result` message) for another node's command it polled
        here, told to that node; None when it is not one."""
        record = self._polled.get(str(result.get("id")))
        if record is None or record.device_id != device.id:
            return None
        del self._polled[record.id]
        record.finish(result["status"], result.get("result"), result.get("error"), time.time_ns())
        self.announce(device, result)
        return record

    def _take_polled(self, fields: dict[str, Any]) -> bool:
        """Another node's command (its record's fields) for a device that polls here: True
        when a poll is waiting, which is woken to take it."""
        device_id, command_id = fields.get("device_id"), fields.get("id")
        if not isinstance(device_id, int) or not isinstance(command_id, str):
            return False
        if command_id not in self._polled:
            try:
                record = CommandRecord(**fields)
            except TypeError:  # not a record of a twinlink node
                return False
            if not self._wake_polls(device_id):
                return False
            if len(self._polled) >= _PRUNE_AT:  # the unanswered ones, once expired
                now = time.time_ns()
                self._polled = {k: r for k, r in self._polled.items() if r.expires_ns > now}
            self._polled[command_id] = record
            return True
        return self._wake_polls(device_id)

    # -- what the bus brings ------------------------------------------------------------------

    def _heard_command(self, subject: str, message: object) -> None:
        if not isinstance(message, dict):
            return
        if message.get("kind") == "push":
            self._heard_push(subject, message)
        elif message.get("kind") == "connected" and message.get("node") != self.node:
            device_id, created_ns = message.get("device"), message.get("created_ns")
            if isinstance(device_id, int) and isinstance(created_ns, int):
                for record in self._queued_for(device_id, created_ns):
                    self._spawn(self.push(record, wait=False))

    def _heard_push(self, subject: str, message: dict[str, Any]) -> None:
        device_id, command_id = message.get("device"), message.get("id")
        session = self.hub.session(device_id) if isinstance(device_id, int) else None
        if not isinstance(command_id, str):
            return
        twin = subject.split(".", 1)[1]
        if session is None:  # a poll here may take it; else not this node's device
            fields = message.get("record")
            if isinstance(fields, dict) and self._take_polled(fields):
                self._publish(f"command-results.{twin}", {"type": "taken", "id": command_id})
            return
        # created_ns: not a command for a deleted device whose id was given to this one
        if int(message.get("created_ns") or 0) < session.device.created_ns:
            return
        known = self._sent.get(command_id)
        if known is None or known[1] is not session:  # each id once per session
            if not session.send(message.get("message") or {}):
                return
            self._remember(command_id, session, int(message.get("expires_ns") or 0))
        self._publish(f"command-results.{twin}", {"type": "taken", "id": command_id})

    def _heard_result(self, subject: str, message: object) -> None:
        if not isinstance(message, dict):
            return
        if message.get("type") == "taken":
            taken = self._taken.get(str(message.get("id")))
            if taken is not None and not taken.done():
                taken.set_result(None)
        elif message.get("node") != self.node:  # this node applied its own already
            self._on_event(message)

    # -- bookkeeping --------------------------------------------------------------------------

    def _remember(self, command_id: str, session: DeviceSession, expires_ns: int) -> None:
        if len(self._sent) >= _PRUNE_AT:
            now = time.time_ns()
            self._sent = {k: v for k, v in self._sent.items() if v[2] > now}
        self._sent[command_id] = (session.device.id, session, expires_ns)

    def _publish(self, subject: str, message: dict[str, Any]) -> None:
        self._spawn(self._publish_now(subject, message))

    async def _publish_now(self, subject: str, message: dict[str, Any]) -> None:
        try:
            await self.bus.publish(subject, message)
        except Exception as err:
            log.warning(
                "a command event could not be told to the other nodes",
                extra={"event": "command_relay_failed", "subject": subject, "error": str(err)},
            )

    def _spawn(self, work: Any) -> None:
        task: asyncio.Task[Any] = asyncio.get_running_loop().create_task(work)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
