"""The OPC UA connector: the platform as an OPC UA client of a machine's server.

It connects (anonymous or username/password, security None or a signed/encrypted channel),
subscribes the configured nodes and stores their data changes as the signals of its device,
and carries the device's commands as node writes and method calls. When the server goes away
or the session dies it reconnects by itself, waiting longer after each failed attempt, and
subscribes again. See docs/opcua.md.

Notifications are gathered into batches (`batch_max_samples`, `batch_window_ms`); a sample's
time is the value's source timestamp (else the server's, else its arrival). Values with a Bad
status code and values of no platform type are counted as errors, not stored.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import random
import time
from collections import OrderedDict
from collections.abc import Callable, Coroutine
from typing import Any

from asyncua.client.client import Client
from asyncua.common.subscription import DataChangeEvent, StatusChangeEvent
from asyncua.ua.uaerrors import UaError
from pydantic import BaseModel

from twinlink.connectors.base import Connector, ConnectorHost, ConnectorStatus
from twinlink.connectors.opcua.client import (
    ClientIdentity,
    explain_attempt,
    load_identity,
    new_client,
    server_certificate_der,
)
from twinlink.connectors.opcua.config import OpcUaConfig
from twinlink.connectors.opcua.session import (
    CommandFailed,
    CommandRunner,
    FailedNode,
    NodeResolver,
    Subscribed,
    read_server_state,
    subscribe,
)
from twinlink.connectors.opcua.values import SampleBatcher, read_data_value
from twinlink.domain.errors import TwinlinkError
from twinlink.tasks import until_first_done

__all__ = ["OpcUaConnector"]

log = logging.getLogger("twinlink.connectors.opcua")

# Errors of a connection attempt or of a session: the server, the network or the
# configuration, never a reason to stop trying.
CONNECTION_ERRORS = (OSError, TimeoutError, UaError, ConnectionError)
REMEMBERED_RESULTS = 256  # a command delivered again (at least once) is answered, not rerun
MAX_FAILED_NODES = 50  # signals listed in the status with their reasons; the rest counted


class SessionLost(TwinlinkError):
    """The session ended; the text says how."""


class OpcUaStatus(ConnectorStatus):
    """The common status, plus the server's endpoint, how many of the signals are monitored
    in the current session and which could not be, each with its reason. `messages` counts
    the data changes received."""

    __slots__ = ("address", "failed_nodes", "failed_nodes_more", "monitored")

    def __init__(self, address: str) -> None:
        super().__init__()
        self.address = address
        self.monitored = 0
        self.failed_nodes: list[FailedNode] = []
        self.failed_nodes_more = 0

    def nodes_failed(self, failed: list[FailedNode]) -> None:
        """The signals a new session could not subscribe: each is a `subscribe_failed` error,
        and the first MAX_FAILED_NODES are listed (a server missing a whole folder of nodes
        would otherwise show only the last one)."""
        for node in failed:
            self.error("subscribe_failed", node.text())
        self.failed_nodes = failed[:MAX_FAILED_NODES]
        self.failed_nodes_more = len(failed) - len(self.failed_nodes)

    def view(self) -> dict[str, Any]:
        failed = [
            {"signal": f.signal, "node": f.node, "reason": f.reason} for f in self.failed_nodes
        ]
        return {
            **super().view(),
            "address": self.address,
            "monitored": self.monitored,
            "failed_nodes": failed,
            "failed_nodes_more": self.failed_nodes_more,
        }


class OpcUaConnector(Connector):
    """Subscribes nodes of an OPC UA server as the signals of a device and carries the
    device's commands as node writes and method calls; reconnects by itself."""

    kind = "opcua"
    Config = OpcUaConfig

    def __init__(self, name: str, config: BaseModel, host: ConnectorHost) -> None:
        super().__init__(name, config, host)
        if not isinstance(config, OpcUaConfig):
            raise TypeError(f"an OPC UA connector needs an OpcUaConfig, not {type(config)}")
        self.settings = config
        self.status: OpcUaStatus = OpcUaStatus(config.url)
        self._identity: ClientIdentity | None = None
        self._server_certificate: bytes | None = None
        self._runner: CommandRunner | None = None
        self._commands: dict[str, asyncio.Task[None]] = {}
        self._answered: OrderedDict[str, tuple[Any, str | None]] = OrderedDict()
        self._last_failure = ""
        self._lost_reason = ""

    # -- life -----------------------------------------------------------------------------

    async def prepare(self) -> None:
        """Read the certificate files (or generate the client's certificate)."""
        self._server_certificate = await asyncio.to_thread(server_certificate_der, self.settings)
        self._identity = await load_identity(self.settings)

    async def run(self) -> None:
        delay = self.settings.reconnect_initial_s
        while True:
            if await self._attempt():
                delay = self.settings.reconnect_initial_s  # it worked for a while: start over
            # Jitter, so connectors of one server that lost it together do not return together.
            await asyncio.sleep(delay * random.uniform(0.8, 1.2))
            delay = min(delay * 2, self.settings.reconnect_max_s)

    async def cleanup(self) -> None:
        tasks = list(self._commands.values())
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    async def _attempt(self) -> bool:
        """One connection, from connecting to losing it; True when it got connected."""
        client: Client | None = None
        lost = asyncio.Event()
        opened = connected = False
        try:
            client = await new_client(self.settings, self._identity, self._server_certificate)
            client.connection_lost_callback = self._on_lost(lost)
            await client.connect()
            opened = True
            subscribed = await self._start_session(client)
            connected = True
            reason = await self._serve(client, subscribed, lost)
            self._report("connection_lost", reason, "reconnecting")
        except CONNECTION_ERRORS as err:
            if opened:  # lost while subscribing or serving: reconnecting will do
                text = f"{self.settings.url}: {err or type(err).__name__}"
                self._report("connection_lost", text, "reconnecting")
            else:
                failure = await explain_attempt(err, self.settings, self._identity)
                self._report(failure.kind, failure.text, failure.state)
        finally:
            self._runner = None
            self.status.monitored = 0
            if client is not None and opened:
                await self._disconnect(client)
            elif client is not None:  # stopped halfway through connecting: drop the socket
                client.disconnect_socket()
            await self._settle_commands()
            await self.close_link()
        return connected

    async def _start_session(self, client: Client) -> Subscribed:
        nodes = NodeResolver(client)
        subscribed = await subscribe(client, self.settings, nodes)
        self.status.nodes_failed(subscribed.failed)
        # Commands queued for the device arrive as soon as it is online: be ready for them.
        self._runner = CommandRunner(client, self.settings, nodes)
        await self.open_link()  # the device is online while the server is
        self.status.monitored = len(subscribed.signals)
        self.status.set_state("connected")
        self._last_failure = ""
        log.info("connected", extra={"event": "opcua_connected", "connector": self.name,
                                     "url": self.settings.url,
                                     "monitored": len(subscribed.signals)})  # fmt: skip
        return subscribed

    def _on_lost(self, lost: asyncio.Event) -> Callable[[Exception], Coroutine[Any, Any, None]]:
        # asyncua calls this when the transport closed (a server that stops answering is
        # noticed by `_watch`).
        async def connection_lost(err: Exception) -> None:
            self._lost_reason = str(err) or type(err).__name__
            lost.set()

        return connection_lost

    def _report(self, kind: str, text: str, state: str) -> None:
        self.status.error(kind, text)
        self.status.set_state(state)
        if text != self._last_failure:  # once per kind of trouble, not once per attempt
            self._last_failure = text
            log.warning("%s", text, extra={"event": f"opcua_{kind}", "connector": self.name})

    async def _disconnect(self, client: Client) -> None:
        with contextlib.suppress(Exception):
            async with asyncio.timeout(self.settings.request_timeout_s):
                await client.disconnect()

    # -- data changes ---------------------------------------------------------------------

    async def _serve(self, client: Client, subscribed: Subscribed, lost: asyncio.Event) -> str:
        """Take the subscription's notifications until the session ends; returns how."""
        batcher = SampleBatcher()
        taking = asyncio.create_task(self._take(subscribed, batcher))
        flushing = asyncio.create_task(self._flush_periodically(batcher))
        watching = asyncio.create_task(self._watch(client))
        losing = asyncio.create_task(lost.wait())
        try:
            error = await until_first_done((taking, flushing, watching, losing))
        finally:
            await self._flush(batcher)
        url = self.settings.url
        if lost.is_set():
            return f"the connection to {url} was lost ({self._lost_reason})"
        if isinstance(error, (SessionLost, *CONNECTION_ERRORS)):
            return f"{url}: {error}"
        if error is not None:
            raise error  # a bug: Connector._run reports it
        return f"the connection to {url} was lost"

    async def _watch(self, client: Client) -> None:
        """Read the server's state every `watchdog_interval_s`; a read not answered within
        `request_timeout_s` ends the session. A server may answer a session's requests one
        at a time (asyncua's does), so the read also waits for the method calls in flight,
        up to when their commands expire."""
        loop = asyncio.get_running_loop()
        while True:
            await asyncio.sleep(self.settings.watchdog_interval_s)
            busy = self._runner.busy_until() if self._runner is not None else None
            waited = 0.0 if busy is None else max(0.0, busy - loop.time())
            try:
                await read_server_state(client, self.settings.request_timeout_s + waited)
            except TimeoutError as err:
                raise SessionLost(self._unanswered(waited)) from err

    def _unanswered(self, waited: float) -> str:
        text = (
            "the server did not answer the watchdog's read of its state within "
            f"{self.settings.request_timeout_s:g} s (request_timeout_s)"
        )
        if waited:
            text += f" after the {waited:.3g} s its method calls in flight could take"
        return text

    async def _take(self, subscribed: Subscribed, batcher: SampleBatcher) -> None:
        max_samples = self.settings.batch_max_samples
        async for event in subscribed.subscription:
            if isinstance(event, DataChangeEvent):
                self._take_change(event, subscribed.signals, batcher)
                if len(batcher) >= max_samples:
                    await self._flush(batcher)
            elif isinstance(event, StatusChangeEvent):
                code = event.notification.Status
                if code is not None and code.is_bad():
                    raise SessionLost(f"the server ended the subscription ({code.name})")
        raise SessionLost("the subscription was closed")

    def _take_change(
        self, event: DataChangeEvent, signals: dict[int, str], batcher: SampleBatcher
    ) -> None:
        item = event.data.monitored_item
        signal = signals.get(item.ClientHandle)
        if signal is None:
            return
        arrival = time.time_ns()
        status = self.status
        status.received(arrival)  # `messages` counts notifications (docs/connectors.md)
        reading = read_data_value(item.Value, arrival)
        if reading.error_kind:
            status.error(reading.error_kind, f"{signal}: {reading.error}")
        else:
            assert reading.value is not None
            batcher.add(reading.time_ns, signal, reading.value)

    async def _flush_periodically(self, batcher: SampleBatcher) -> None:
        interval = self.settings.batch_window_ms / 1000
        while True:
            await batcher.has_samples.wait()
            await asyncio.sleep(interval)
            await self._flush(batcher)

    async def _flush(self, batcher: SampleBatcher) -> None:
        samples = batcher.take()
        if not samples:
            return
        await self.send_samples(samples, self.settings.stream)

    # -- commands -------------------------------------------------------------------------

    async def on_message(self, message: dict[str, Any]) -> None:
        if message.get("type") != "command":
            return  # welcome, desired properties: nothing an OPC UA server is told
        command_id = str(message.get("id"))
        if command_id in self._commands:
            return  # delivered again while running: its result is on the way
        args = message.get("args")
        name = str(message.get("name"))
        deadline = _deadline(message.get("expires"))
        task = asyncio.create_task(
            self._command(command_id, name, args if isinstance(args, dict) else {}, deadline),
            name=f"connector-{self.name}-command",
        )
        self._commands[command_id] = task
        task.add_done_callback(lambda _: self._commands.pop(command_id, None))

    async def _command(
        self, command_id: str, name: str, args: dict[str, Any], deadline: float | None
    ) -> None:
        if command_id in self._answered:
            result, error = self._answered[command_id]
        else:
            result, error = await self._carry_out(name, args, deadline)
            self._answered[command_id] = (result, error)
            while len(self._answered) > REMEMBERED_RESULTS:
                self._answered.popitem(last=False)
            if error is not None:
                self.status.error("command_failed", f"{name}: {error}")
        await self.answer(command_id, result=result, error=error)

    async def _carry_out(
        self, name: str, args: dict[str, Any], deadline: float | None
    ) -> tuple[Any, str | None]:
        """Every request of a command has its own limit (`request_timeout_s`, or for a method
        call the time until the command expires), so no limit is set around them."""
        commands = self.settings.commands
        if name not in commands:
            known = ", ".join(sorted(commands)) or "none"
            return None, f"no command {name!r} in this OPC UA connector; it knows: {known}"
        runner = self._runner
        if runner is None:
            state = self.status.state
            return None, f"not connected to the OPC UA server ({state}); try again when connected"
        try:
            return await runner.run(name, args, deadline), None
        except CommandFailed as err:
            return None, str(err)
        except CONNECTION_ERRORS as err:
            return None, f"the connection to the OPC UA server failed: {err or type(err).__name__}"

    async def _settle_commands(self) -> None:
        """Let commands of the ended session fail (their client is gone) and be answered."""
        tasks = list(self._commands.values())
        if tasks:
            await asyncio.wait(tasks, timeout=self.settings.request_timeout_s)


def _deadline(expires: Any) -> float | None:
    """When a command expires (`expires`, ns since the epoch) as event loop time."""
    if not isinstance(expires, int) or isinstance(expires, bool):
        return None
    return asyncio.get_running_loop().time() + (expires - time.time_ns()) / 1e9
