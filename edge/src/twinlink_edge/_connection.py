"""The device's WebSocket: connect, reconnect with backoff, send batches (a window of them in
flight) and control messages, and read what the server says."""

from __future__ import annotations

import asyncio
import logging
import time
from collections import deque
from typing import TYPE_CHECKING, Any, Callable

from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed, InvalidStatus

from . import __version__
from ._batcher import Batcher
from ._protocol import MAX_FRAME_BYTES, Ack, Backoff, JsonObject, loads

if TYPE_CHECKING:
    from .aio import AsyncDevice

log = logging.getLogger("twinlink_edge")

CLOSE_REVOKED = 4401
CLOSE_REPLACED = 4409
RETRY_DELAY = 1.0  # seconds before a batch the server could not store goes out again
STABLE_SESSION = 5.0  # seconds a connection must last before the backoff starts over


class Connection:
    def __init__(
        self,
        device: AsyncDevice,
        batcher: Batcher,
        token: str,
        *,
        window: int,
        backoff: tuple[float, float],
        connect_timeout: float,
        ping_interval: float | None,
        compression: str | None,
    ) -> None:
        self.device = device
        self.batcher = batcher
        self.window = window
        self.backoff = Backoff(*backoff)
        self.connect_timeout = connect_timeout
        self.connected = False
        self.connections = 0
        self._headers = {"Authorization": f"Bearer {token}"}
        self._options: dict[str, Any] = {
            "open_timeout": connect_timeout,
            "ping_interval": ping_interval,
            "ping_timeout": ping_interval,
            "close_timeout": 2,
            "max_size": MAX_FRAME_BYTES,
            "compression": compression,
            "user_agent_header": f"twinlink-edge/{__version__}",
        }
        self._inflight: set[int] = set()
        # Round trips (`ControlQueue.round_trip`) whose ping went out on this connection, in
        # order: the server answers pings in order, and a pong carries no id.
        self._pings: deque[asyncio.Future[None]] = deque()
        self._since: float | None = None  # when the current connection was welcomed
        self._up: asyncio.Event | None = None
        self._handlers: dict[str, Callable[[JsonObject], None]] = {
            "ack": self._on_ack,
            "error": self._on_error,
            "command": self._on_command,
            "desired": self._on_desired,
            "reported_ack": self._on_reported_ack,
            "welcome": self._on_welcome,
            "pong": self._on_pong,
        }

    def start(self) -> None:
        self._up = asyncio.Event()

    async def wait_connected(self, timeout: float | None) -> bool:
        assert self._up is not None
        try:
            await asyncio.wait_for(self._up.wait(), timeout)
        except asyncio.TimeoutError:
            return False
        return True

    async def run(self) -> None:
        """Connect, and connect again whenever the connection ends, until cancelled."""
        loop = asyncio.get_running_loop()
        while True:
            self._since = None
            try:
                async with connect(
                    self.device.url, additional_headers=self._headers, **self._options
                ) as ws:
                    await self._session(ws)
                    self._closed_by_server(ws.close_code, ws.close_reason)
            except asyncio.CancelledError:
                raise
            except Exception as e:
                self._failed(e)
            finally:
                self._down()
            if self._since is not None and loop.time() - self._since >= STABLE_SESSION:
                self.backoff.reset()
            delay = self.backoff.next()
            log.debug("reconnecting in %.2f s", delay)
            await asyncio.sleep(delay)

    def _failed(self, e: Exception) -> None:
        if isinstance(e, InvalidStatus) and e.response.status_code in (401, 403):
            text = f"the server refused the device token ({e.response.status_code})"
            log.error("%s; retrying", text)
        elif (
            isinstance(e, ConnectionClosed)
            and e.rcvd is not None
            and e.rcvd.code
            in (
                CLOSE_REVOKED,
                CLOSE_REPLACED,
            )
        ):
            self._closed_by_server(e.rcvd.code, e.rcvd.reason)
            return
        elif isinstance(e, ConnectionClosed):
            text = f"connection lost: {e}"
            log.warning("%s", text)
        else:
            text = f"cannot connect to {self.device.url}: {type(e).__name__}: {e}"
            log.warning("%s", text)
        self.device.last_error = text

    def _closed_by_server(self, code: int | None, reason: str | None) -> None:
        if code == CLOSE_REVOKED:
            log.error("the server refused the device token: %s; retrying", reason)
        elif code == CLOSE_REPLACED:
            log.error("another connection with this device's token replaced this one")
        else:
            log.warning("the server closed the connection (%s %s)", code, reason or "")
        self.device.last_error = f"closed by the server ({code} {reason or ''})".strip()
        if code == CLOSE_REVOKED:
            self.device.last_error = f"the server refused the device token ({code} {reason})"

    def _down(self) -> None:
        if self.connected:
            log.info("disconnected")
        self.connected = False
        if self._up is not None:
            self._up.clear()
        # A ping lost with its connection goes out again on the next one, after what waits
        # there: a round trip counts only when it was made on one connection.
        self.device._control.again(list(self._pings))
        self._pings.clear()

    async def _session(self, ws: ClientConnection) -> None:
        await asyncio.wait_for(self._welcome(ws), self.connect_timeout)
        self.batcher.rewind()
        self._inflight.clear()
        self.device._reports.rewind()
        self.connected = True
        self.connections += 1
        self._since = asyncio.get_running_loop().time()
        assert self._up is not None
        self._up.set()
        dev = self.device
        log.info("connected to %s as %s (twin %s)", dev.url, dev.device_name, dev.twin)
        reader = asyncio.ensure_future(self._reader(ws))
        sender = asyncio.ensure_future(self._sender(ws))
        try:
            done, _ = await asyncio.wait({reader, sender}, return_when=asyncio.FIRST_COMPLETED)
        finally:
            reader.cancel()
            sender.cancel()
            await asyncio.gather(reader, sender, return_exceptions=True)
        for task in done:
            if not task.cancelled() and task.exception() is not None:
                raise task.exception()  # type: ignore[misc]

    async def _welcome(self, ws: ClientConnection) -> None:
        """Read until the `welcome` (handling anything else that comes first)."""
        while True:
            msg = self._decode(await ws.recv())
            if msg is not None and msg.get("type") == "welcome":
                self._on_welcome(msg)
                return
            if msg is not None:
                self._dispatch(msg)

    async def _reader(self, ws: ClientConnection) -> None:
        async for raw in ws:
            msg = self._decode(raw)
            if msg is not None:
                self._dispatch(msg)

    async def _sender(self, ws: ClientConnection) -> None:
        dev = self.device
        work = dev._work
        assert work is not None
        while True:
            work.clear()
            while (item := dev._control.next()) is not None:
                try:
                    await ws.send(dev._control.text_of(item))
                except BaseException:
                    dev._control.put_back(item)
                    raise
                if not isinstance(item, str):
                    self._pings.append(item)
            while (report := dev._reports.next_unsent()) is not None:
                await ws.send(report)
            while len(self._inflight) < self.window:
                batch = self.batcher.next_to_send()
                if batch is None:
                    break
                self._inflight.add(batch.seq)
                await ws.send(batch.payload)
            await work.wait()

    # ---- server messages ---------------------------------------------------------------

    @staticmethod
    def _decode(raw: str | bytes) -> JsonObject | None:
        try:
            msg = loads(raw)
        except ValueError:
            log.warning("the server sent a frame that is not JSON: %.200r", raw)
            return None
        if not isinstance(msg, dict):
            log.warning("the server sent a frame that is not an object: %.200r", raw)
            return None
        return msg

    def _dispatch(self, msg: JsonObject) -> None:
        handler = self._handlers.get(str(msg.get("type")))
        if handler is None:
            log.debug("ignoring a message of type %r", msg.get("type"))
            return
        try:
            handler(msg)
        except Exception:  # a message we do not understand must not end the connection
            log.exception("cannot handle the server's message %.200s", msg)

    def _on_welcome(self, msg: JsonObject) -> None:
        dev = self.device
        dev.device_name = msg.get("device")
        dev.twin = msg.get("twin")
        server_time = msg.get("server_time")
        if isinstance(server_time, int):
            dev.server_clock_offset_ns = server_time - time.time_ns()
        self._desired(msg.get("desired"), msg.get("desired_version"), always=False)

    def _desired(self, delta: Any, version: Any, *, always: bool) -> None:
        """The server's desired delta (desired values that differ from the reported ones).
        The handlers hear of it when it holds a value the last one did not, or `always` (a
        `desired` message, sent when the desired values changed)."""
        dev = self.device
        if isinstance(version, int) and not isinstance(version, bool):
            dev.desired_version = version
        if not isinstance(delta, dict):
            return
        old, dev.desired = dev.desired, dict(delta)
        news = any(k not in old or old[k] != v for k, v in delta.items())
        if delta and (news or always):
            dev._dispatcher.desired(dict(delta))

    def _on_ack(self, msg: JsonObject) -> None:
        ack = Ack.from_message(msg)
        self._inflight.discard(ack.seq)
        self.device._answered(ack, self.batcher.remove(ack.seq))

    def _on_error(self, msg: JsonObject) -> None:
        text = str(msg.get("message", "")) or "(no message)"
        seq = msg.get("seq")
        self.device.last_error = text
        if isinstance(seq, int) and not isinstance(seq, bool):
            self._inflight.discard(seq)
            if msg.get("retry") is True:
                log.warning("batch %d not stored (%s); sending it again in %s s", seq, text,
                            RETRY_DELAY)  # fmt: skip
                asyncio.get_running_loop().call_later(RETRY_DELAY, self._retry, seq)
            else:
                ack = Ack(seq=seq, refused=text, raw=msg)
                self.device._answered(ack, self.batcher.remove(seq))
        elif self.device._reports.refused(msg):
            log.error("reported properties refused by the server: %s", text)
        elif msg.get("fatal"):
            log.error("the server ends the connection: %s", text)
        else:
            log.warning("the server says: %s", text)

    def _retry(self, seq: int) -> None:
        if self.batcher.requeue(seq) and self.device._work is not None:
            self.device._work.set()

    def _on_command(self, msg: JsonObject) -> None:
        self.device._dispatcher.command(msg)

    def _on_desired(self, msg: JsonObject) -> None:
        if not isinstance(msg.get("properties"), dict):
            log.warning("a desired message without properties: %.200s", msg)
            return
        self._desired(msg["properties"], msg.get("version"), always=True)

    def _on_pong(self, msg: JsonObject) -> None:
        if not self._pings:
            log.debug("a pong for no ping")
            return
        fut = self._pings.popleft()
        if not fut.done():
            fut.set_result(None)

    def _on_reported_ack(self, msg: JsonObject) -> None:
        dev = self.device
        version = msg.get("version")
        if isinstance(version, int):
            dev.reported_version = version
        if not dev._reports.acked(msg):
            log.debug("a reported_ack for no report")
        self._desired(msg.get("desired"), version, always=False)
