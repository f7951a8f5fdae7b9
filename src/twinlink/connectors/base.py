"""What every connector shares: its status, its host (the device it speaks for) and the
transport that turns the platform's messages to the device into protocol actions.

A connector (a UDP datasource, an OPC UA client, ...) speaks for one device of one twin. It
opens that device's session through its `ConnectorHost`, exactly as a device opening the
device WebSocket would (docs/protocol.md): batches it builds go in through
`DeviceLink.dispatch` and are acknowledged once durable; commands, desired properties, acks
and errors come back to it through `ConnectorTransport.deliver`. So history, live views,
processors, the command log and device status work for connectors with nothing added.
"""

from __future__ import annotations

import asyncio
import logging
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import orjson
from pydantic import BaseModel

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.records import Device
from twinlink.ingest.health import Health
from twinlink.ingest.link import DeviceLink, ServerSeq, connect_device, disconnect_device
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub

log = logging.getLogger("twinlink.connectors")


class ConnectorError(TwinlinkError):
    """A connector cannot start as configured (address in use, bad format...); the message
    says what to change."""


@dataclass(slots=True)
class ConnectorStatus(Health):
    """What `twinlink connectors ls` and the API show. `state` is one of: stopped, starting,
    listening (a server side waiting for peers), connected, reconnecting, error."""

    last_message_ns: int | None = None
    messages: int = 0
    samples: int = 0
    rejected: int = 0
    commands: int = 0

    def received(self, at_ns: int) -> None:
        """One message (a datagram, a notification) taken in at `at_ns`."""
        self.messages += 1
        self.last_message_ns = at_ns

    def view(self) -> dict[str, Any]:
        return {
            **self.health_view(),
            "last_message_ns": self.last_message_ns,
            "messages": self.messages,
            "samples": self.samples,
            "rejected": self.rejected,
            "commands": self.commands,
        }


class ConnectorHost(Protocol):
    """The device a connector speaks for, and the way into the platform."""

    device: Device

    async def connect(self, transport: ConnectorTransport) -> DeviceLink: ...

    async def disconnect(self, link: DeviceLink) -> None: ...


class LinkHost:
    """The host the server gives a connector: its device's session on the device hub."""

    def __init__(self, hub: DeviceHub, ingest: IngestService, device: Device) -> None:
        self.hub = hub
        self.ingest = ingest
        self.device = device

    async def connect(self, transport: ConnectorTransport) -> DeviceLink:
        return await connect_device(self.hub, self.ingest, self.device, transport)

    async def disconnect(self, link: DeviceLink) -> None:
        await disconnect_device(link)


class ConnectorTransport:
    """The `Transport` of a connector's device session: what the platform sends the device
    arrives here as text and is handed to the connector as a dict. Acks and errors about
    batches update the status; everything else (command, desired, welcome) goes to
    `Connector.on_message`."""

    def __init__(self, connector: Connector) -> None:
        self.connector = connector

    async def send_text(self, data: str) -> None:
        message = orjson.loads(data)
        kind = message.get("type")
        status = self.connector.status
        if kind == "ack":
            status.rejected += int(message.get("rejected_count", 0))
            for rejection in message.get("rejected", [])[:1]:
                status.error("rejected_sample", str(rejection.get("reason")))
        elif kind == "error":
            status.error("refused_batch", str(message.get("message")))
        elif kind == "pong":
            return
        else:
            if kind == "command":
                status.commands += 1
            await self.connector.on_message(message)

    async def close(self, code: int, reason: str) -> None:
        # The session was closed by the platform (device deleted, replaced by another
        # connection): the connector stops taking data for it.
        self.connector.session_closed(code, reason)


class Connector(ABC):
    """One configured connector. Subclasses set `kind` and `Config`, and implement `run`
    (the connector's life: connect, receive, reconnect, until cancelled)."""

    kind: ClassVar[str]
    Config: ClassVar[type[BaseModel]]

    def __init__(self, name: str, config: BaseModel, host: ConnectorHost) -> None:
        self.name = name
        self.config = config
        self.host = host
        self.status = ConnectorStatus()
        self.seq = ServerSeq()
        self.link: DeviceLink | None = None
        self._task: asyncio.Task[None] | None = None

    # -- life ---------------------------------------------------------------------------

    async def start(self) -> None:
        """Start; raises ConnectorError when the configuration cannot work at all (a port
        in use, say). Connection failures after that are retried by `run`, not raised."""
        self.status.set_state("starting")
        await self.prepare()
        self._task = asyncio.create_task(self._run(), name=f"connector-{self.name}")

    async def stop(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
            self._task = None
        await self.close_link()
        await self.cleanup()
        self.status.set_state("stopped")

    async def _run(self) -> None:
        try:
            await self.run()
        except asyncio.CancelledError:
            raise
        except Exception as err:  # a bug or a state the connector did not expect
            log.exception("connector failed", extra={"event": "connector_failed",
                                                     "connector": self.name})  # fmt: skip
            self.status.error("failed", str(err) or type(err).__name__)
            self.status.set_state("error")

    async def prepare(self) -> None:  # noqa: B027 (an optional hook)
        """Bind sockets and check what can be checked before `start` returns."""

    @abstractmethod
    async def run(self) -> None: ...

    async def cleanup(self) -> None:  # noqa: B027 (an optional hook)
        """Release what `prepare` took."""

    # -- the device session -------------------------------------------------------------

    async def open_link(self) -> DeviceLink:
        if self.link is None or self.link.session.closed.is_set():
            self.link = await self.host.connect(ConnectorTransport(self))
        return self.link

    async def close_link(self) -> None:
        link, self.link = self.link, None
        if link is not None:
            await self.host.disconnect(link)

    async def send_samples(self, samples: list[dict[str, Any]], stream: str) -> None:
        """Hand one batch of samples (`{"time": ns, "values": {...}}`) to the platform;
        its ack arrives at the transport once the batch is durable. Messages are counted
        where they arrive (`status.received`): a batch gathers many of them."""
        link = await self.open_link()
        await link.dispatch(
            {"type": "samples", "seq": self.seq.next(), "stream": stream, "samples": samples}
        )
        self.status.samples += len(samples)

    async def answer(self, command_id: str, result: Any = None, error: str | None = None) -> None:
        """Report a command's outcome, as a device would."""
        if self.link is None:
            return
        message: dict[str, Any] = {"type": "result", "id": command_id}
        if error is None:
            message.update(status="succeeded", result=result)
        else:
            message.update(status="failed", error=error)
        await self.link.dispatch(message)

    # -- what the platform sends --------------------------------------------------------

    async def on_message(self, message: dict[str, Any]) -> None:
        """A message for the device: by default a command is refused with a reason."""
        if message.get("type") == "command":
            await self.answer(
                str(message.get("id")), error=f"a {self.kind} connector cannot carry commands"
            )

    def session_closed(self, code: int, reason: str) -> None:
        if code not in (1000, 4409):
            self.status.error("session_closed", reason or f"code {code}")
