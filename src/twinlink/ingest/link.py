"""A connected device's messages, whatever carries them.

The device WebSocket, MQTT and the connectors (UDP, OPC UA) all end in the same place: a
`DeviceSession` for what goes to the device (welcome, acks, commands, desired properties) and
a `DeviceLink` for what comes from it (sample batches, pings, command results, reported
properties). A transport only turns its frames into these messages and back.
"""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

from twinlink.domain.errors import StorageError, TooManySignalsError, UnavailableError
from twinlink.domain.records import Device
from twinlink.domain.samples import BatchError
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub, DeviceSession, Transport

log = logging.getLogger("twinlink.ingest")

MAX_IN_FLIGHT = 64  # batches of one connection being stored at once


async def connect_device(
    hub: DeviceHub, ingest: IngestService, device: Device, transport: Transport
) -> DeviceLink:
    """Make `transport` the device's connection: an older one is closed, the welcome is the
    first message it carries, queued commands and desired properties follow."""
    session = DeviceSession(device, transport)
    await hub.attach(session)
    session.open(
        {
            "type": "welcome",
            "device": device.name,
            "twin": device.twin_slug,
            "server_time": time.time_ns(),
            **await hub.welcome(device),
        }
    )
    await hub.connected(session)
    log.info("device connected", extra={"event": "device_connected", "device": device.name,
                                        "twin": device.twin_slug})  # fmt: skip
    return DeviceLink(session, ingest, hub)


async def disconnect_device(link: DeviceLink) -> None:
    """The connection ended: batches being stored still land, then the session closes."""
    link.hub.detach(link.session)
    await link.finish()
    await link.session.close()
    log.info("device disconnected", extra={"event": "device_disconnected",
                                           "device": link.session.device.name})  # fmt: skip


class ServerSeq:
    """Sequence numbers for batches a transport makes itself (a datagram, an MQTT message
    without `seq`, an OPC UA notification): the time in ns, kept increasing, so they never
    repeat a number the device's earlier batches used and are never taken for resends."""

    def __init__(self) -> None:
        self._last = 0

    def next(self) -> int:
        self._last = max(self._last + 1, time.time_ns())
        return self._last


class DeviceLink:
    """Messages from one device, dispatched by `type` (docs/protocol.md)."""

    def __init__(self, session: DeviceSession, ingest: IngestService, hub: DeviceHub) -> None:
        self.session = session
        self.ingest = ingest
        self.hub = hub
        self.tasks: set[asyncio.Task[None]] = set()  # batches being stored
        self._room: asyncio.Future[None] | None = None  # set when `tasks` has room again

    async def dispatch(self, message: dict[str, Any]) -> None:
        kind = message.get("type")
        if kind == "samples":  # errors about a batch name it by `seq`
            # Storing runs beside reading, so batches that arrive together share a commit;
            # reading stops while too many are waiting (back-pressure). A count of the tasks,
            # not a semaphore: this runs for every batch of every device.
            while len(self.tasks) >= MAX_IN_FLIGHT:
                self._room = asyncio.get_running_loop().create_future()
                await self._room
            task = asyncio.create_task(self.store(message))
            self.tasks.add(task)
            task.add_done_callback(self._stored)
        elif kind == "ping":
            self.session.send({"type": "pong", "server_time": time.time_ns()})
        elif isinstance(kind, str) and kind in self.hub.handlers:
            try:
                reply = await self.hub.handlers[kind](self.session, message)
            except ValueError as err:
                self.error(str(err), op=kind, ref=message.get("id"))
                return
            if reply is not None:
                self.session.send(reply)
        else:
            known = ", ".join(sorted({"samples", "ping", *self.hub.handlers}))
            self.error(f"unknown message type {kind!r}; expected one of {known}")

    async def store(self, message: dict[str, Any]) -> None:
        device: Device = self.session.device
        seq = message.get("seq")
        try:
            ack = await self.ingest.ingest(device, message)
        except (BatchError, TooManySignalsError) as err:
            self.error(str(err), seq=seq)
        except StorageError as err:  # counted and logged (once a minute) by the store
            self.error(str(err), seq=seq, retry=True)
        except UnavailableError as err:  # the bus (Kafka) away: stored or not, send it again
            self.error(str(err), seq=seq, retry=True)
        except Exception:
            log.exception("storing a batch failed", extra={"event": "ingest_failed"})
            self.error("the batch could not be stored; send it again", seq=seq, retry=True)
        else:
            self.session.send(ack.message())

    def _stored(self, task: asyncio.Task[None]) -> None:
        self.tasks.discard(task)
        if self._room is not None and not self._room.done():
            self._room.set_result(None)

    def error(
        self, text: str, seq: Any = None, retry: bool = False, op: str = "", ref: Any = None
    ) -> None:
        message: dict[str, Any] = {"type": "error", "message": text, "fatal": False}
        if op:  # the type of the message this answers, and its `id` when it had one
            message["op"] = op
            if isinstance(ref, str | int) and not isinstance(ref, bool):
                message["id"] = ref
        if isinstance(seq, int):
            message["seq"] = seq
        if retry:  # nothing wrong with the batch: a transient failure; resend it as it was
            message["retry"] = True
        self.session.send(message)

    async def finish(self) -> None:
        # Batches already being stored still land (the device resends them, unacked, and
        # the sequence number makes that harmless).
        if self.tasks:
            await asyncio.gather(*self.tasks, return_exceptions=True)
