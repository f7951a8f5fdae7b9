"""`AsyncDevice`: the asyncio device client."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import threading
from typing import Any, Callable, TypeVar

from ._batcher import Batcher, check_options
from ._buffer import Buffer, DiskBuffer, MemoryBuffer
from ._connection import Connection
from ._control import ControlQueue
from ._handlers import AnyCommandHandler, DesiredHandler, Dispatcher
from ._inbox import NOT_READ
from ._protocol import (
    Ack,
    BufferFull,
    JsonObject,
    check_stream,
    device_ws_url,
    sample,
)
from ._reports import Reports

log = logging.getLogger("twinlink_edge")

F = TypeVar("F", bound=Callable[..., Any])


class AsyncDevice:
    """A device connected to twinlink over its WebSocket, from asyncio code.

    ```python
    async with AsyncDevice("https://twins.example.org", token) as dev:
        dev.add({"temperature": 21.5})   # cheap, no I/O: batched and sent in the background
        await dev.flush()                # everything added so far is durable on the server
    ```

    Samples are sealed into a batch when `batch_size` wait or `flush_interval` seconds after
    the first of them; up to `window` batches are in flight at once. Batches wait in `buffer`
    (memory, or a folder for a `DiskBuffer`) until their ack, and go out again after a
    reconnect. With `durable=True` (and a folder), `add` returns once the sample itself is in
    the folder's file, so a crash of the program loses none of the samples added. At most
    `max_buffered_samples` wait; then `on_full` decides: `"block"` (`add` from another thread
    waits, `await send()` waits, `add` on the event loop raises `BufferFull`), `"drop_oldest"`
    (the oldest batch is dropped) or `"error"` (`BufferFull`). `add` before `start` raises
    `RuntimeError`, as `flush` does."""

    def __init__(
        self,
        url: str,
        token: str,
        *,
        stream: str = "telemetry",
        batch_size: int = 1000,
        flush_interval: float = 0.05,
        window: int = 16,
        buffer: Buffer | str | os.PathLike[str] | None = None,
        durable: bool = False,
        max_buffered_samples: int = 1_000_000,
        on_full: str = "block",
        backoff_initial: float = 0.1,
        backoff_max: float = 10.0,
        connect_timeout: float = 10.0,
        close_timeout: float = 10.0,
        ping_interval: float | None = 10.0,
        compression: str | None = "deflate",
        on_ack: Callable[[Ack], Any] | None = None,
    ) -> None:
        check_options(token, batch_size, flush_interval, window, max_buffered_samples, on_full)
        if durable and buffer is None:
            raise ValueError("durable=True writes each sample to the device's disk: give `buffer`")
        self.url = device_ws_url(url)
        self.stream = check_stream(stream)
        self.flush_interval = flush_interval
        self.close_timeout = close_timeout
        self.on_ack = on_ack
        if buffer is None:
            buffer = MemoryBuffer()
        elif not isinstance(buffer, Buffer):
            buffer = DiskBuffer(buffer)
        self._batcher = Batcher(
            buffer,
            batch_size=batch_size,
            max_samples=max_buffered_samples,
            on_full=on_full,
            notify=self._notify,
            durable=durable,
        )
        self._control = ControlQueue(self._wake)  # command answers, pings
        self._dispatcher = Dispatcher(self._control.put)
        self._conn = Connection(
            self,
            self._batcher,
            token,
            window=window,
            backoff=(backoff_initial, backoff_max),
            connect_timeout=connect_timeout,
            ping_interval=ping_interval,
            compression=compression,
        )
        self._init_state()

    def _init_state(self) -> None:
        # What the server said
        self.device_name: str | None = None
        self.twin: str | None = None
        self.desired: JsonObject = {}  # the desired values that differ from the reported
        self.desired_version: int | None = None
        self.reported: JsonObject = {}  # what this device reported
        self.reported_version: int | None = None
        self.server_clock_offset_ns = 0  # server clock - device clock, at the last welcome
        self.last_error: str | None = None
        # Counters
        self.acked_samples = 0  # samples of batches answered (accepted or rejected)
        self.accepted_samples = 0
        self.rejected = 0  # samples the server rejected, or refused with their batch
        self.server_timed_samples = 0
        self.duplicate_batches = 0
        self.refused_batches = 0
        # Loop-bound state, made by start()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._loop_thread: int | None = None
        self._work: asyncio.Event | None = None  # something to send
        self._pending: asyncio.Event | None = None  # samples wait to be sealed
        self._space: asyncio.Event | None = None  # room in the buffer
        self._flush_waiters: list[tuple[int, asyncio.Future[None]]] = []
        self._reports = Reports()
        self._tasks: list[asyncio.Task[None]] = []
        self._closed = False

    # ---- lifecycle ---------------------------------------------------------------------

    async def start(self) -> None:
        """Start connecting (in the background: this returns at once) and sending."""
        if self._closed:
            raise RuntimeError("the device is closed")
        if self._loop is not None:
            return
        self._loop = asyncio.get_running_loop()
        self._loop_thread = threading.get_ident()
        self._work, self._pending, self._space = asyncio.Event(), asyncio.Event(), asyncio.Event()
        self._conn.start()
        self._work.set()
        if self._batcher.pending_samples:
            self._pending.set()
        self._tasks = [
            asyncio.ensure_future(self._conn.run()),
            asyncio.ensure_future(self._flush_loop()),
        ]

    async def close(self, timeout: float | None = None) -> None:
        """Wait up to `timeout` (default `close_timeout`) seconds for the acks of everything
        added and for the server to take the command answers, then disconnect. A disk buffer
        keeps what is still unacknowledged. Commands the program never took (compat's
        `receive()`) are answered `failed`, "not read by the device"."""
        if self._closed:
            return
        if self._loop is not None:
            await self._finish(self.close_timeout if timeout is None else timeout)
        self._closed = True
        for task in self._tasks:
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
        await self._dispatcher.stop()
        for _, waiter in self._flush_waiters:
            waiter.cancel()
        self._flush_waiters.clear()
        self._reports.cancel()
        if self._space is not None:
            self._space.set()
        self._batcher.close()

    async def _finish(self, timeout: float) -> None:
        """The last words before a close, within `timeout` seconds."""
        assert self._loop is not None
        deadline = self._loop.time() + timeout
        self._dispatcher.refuse_held(NOT_READ)
        try:
            await self.flush(timeout)
        except TimeoutError:
            where = "kept on disk" if isinstance(self._batcher.buffer, DiskBuffer) else "lost"
            n = self._batcher.buffered_samples
            log.warning("closing with %d samples unacknowledged (%s)", n, where)
        if not self._control.unconfirmed:
            return
        # The server handles messages in order: once it answers a ping sent after the
        # command answers, it has them all.
        try:
            await self._round_trip(max(0.0, deadline - self._loop.time()))
        except TimeoutError:
            log.warning("closing before the server confirmed the command answers")

    def _close_unstarted(self) -> None:
        """Close a device that never started (nothing runs: only the buffer to close)."""
        if self._loop is None and not self._closed:
            self._closed = True
            self._batcher.close()

    async def __aenter__(self) -> AsyncDevice:
        await self.start()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    # ---- samples -----------------------------------------------------------------------

    def add(
        self, values: JsonObject, time_ns: int | None = None, stream: str | None = None
    ) -> None:
        """Queue one sample (`time_ns`: nanoseconds since the epoch, default now). Safe to
        call from any thread; no I/O, except that with a disk buffer the call that completes
        a batch writes it, and with `durable=True` every call writes its sample."""
        if self._loop_thread is None:  # a sample would wait for a start that may not come
            raise RuntimeError("the device is not running: call start() first")
        item = sample(values, time_ns)
        here = self._loop_thread == threading.get_ident()
        if not self._batcher.add(item, stream or self.stream, wait=not here):
            raise BufferFull("the buffer is full: from the event loop, await send() waits")

    async def send(
        self, values: JsonObject, time_ns: int | None = None, stream: str | None = None
    ) -> None:
        """Like `add`, but waits for room in a full buffer under `on_full="block"`."""
        item = sample(values, time_ns)
        space = self._started()._space
        assert space is not None
        while True:
            space.clear()
            if self._batcher.add(item, stream or self.stream, wait=False):
                return
            await space.wait()

    async def flush(self, timeout: float | None = None) -> None:
        """Wait until every sample added so far is acknowledged (or dropped)."""
        loop = self._started()._loop
        assert loop is not None
        target = self._batcher.seal_all()
        if self._batcher.done_through(target):
            return
        fut: asyncio.Future[None] = loop.create_future()
        self._flush_waiters.append((target, fut))
        try:
            await asyncio.wait_for(fut, timeout)
        except asyncio.TimeoutError:
            n = self._batcher.buffered_samples
            raise TimeoutError(f"{n} samples still unacknowledged after {timeout} s") from None

    # ---- commands and properties -------------------------------------------------------

    def on_command(self, name: str) -> Callable[[F], F]:
        """Decorator: `handler(args: dict)` runs command `name`; what it returns (JSON-able)
        is the result, an exception fails the command with its text. Sync or async."""
        return self._dispatcher.on_command(name)

    def on_any_command(self, handler: AnyCommandHandler) -> AnyCommandHandler:
        """`handler(name, args)` runs commands that have no handler of their own."""
        self._dispatcher.fallback = handler
        return handler

    def on_desired(self, handler: DesiredHandler) -> DesiredHandler:
        """`handler(delta: dict)` is called with the desired values that differ from the
        reported ones, whenever the server sends them changed (on connect, after a change of
        the desired values, after a report). `self.desired` holds the latest delta; a handler
        registered while it holds values is called with them at once."""
        self._dispatcher.desired_handlers.append(handler)
        if self._loop is not None and self.desired:
            self._dispatcher.desired(dict(self.desired), only=handler)
        return handler

    async def report(
        self, properties: JsonObject, *, wait: bool = True, timeout: float | None = None
    ) -> int | None:
        """Send reported properties. With `wait`, return the version the server gave them
        (`ReportError` when it refuses them); a report not answered yet goes out again after
        a reconnect."""
        if not isinstance(properties, dict) or not properties:
            raise ValueError("report a non-empty dict of properties")
        loop = self._started()._loop
        assert loop is not None and self._work is not None
        fut: asyncio.Future[int] = loop.create_future()
        self._reports.add(properties, fut)
        self.reported.update(properties)
        self._work.set()
        if not wait:
            return None
        try:
            return await asyncio.wait_for(asyncio.shield(fut), timeout)
        except asyncio.TimeoutError:
            raise TimeoutError(f"no reported_ack after {timeout} s") from None

    async def _round_trip(self, timeout: float | None = None) -> None:
        """A ping and its pong (`ControlQueue.round_trip`): the server has the command
        answers sent before, the device the messages the server sent before."""
        await self._started()._control.round_trip(timeout)

    # ---- state -------------------------------------------------------------------------

    @property
    def connected(self) -> bool:
        return self._conn.connected

    @property
    def connections(self) -> int:
        """How many times the device connected (1 + reconnects)."""
        return self._conn.connections

    @property
    def buffered_samples(self) -> int:
        return self._batcher.buffered_samples

    @property
    def dropped_samples(self) -> int:
        return self._batcher.dropped_samples

    async def wait_connected(self, timeout: float | None = None) -> bool:
        """Wait until the device is connected; False on timeout."""
        self._started()
        return await self._conn.wait_connected(timeout)

    def stats(self) -> dict[str, Any]:
        return {
            "connected": self.connected,
            "connections": self.connections,
            "acked_samples": self.acked_samples,
            "accepted_samples": self.accepted_samples,
            "rejected": self.rejected,
            "server_timed_samples": self.server_timed_samples,
            "duplicate_batches": self.duplicate_batches,
            "refused_batches": self.refused_batches,
            **self._batcher.counts(),
        }

    # ---- internals, called by Connection and Batcher ------------------------------------

    def _started(self) -> AsyncDevice:
        if self._loop is None or self._closed:
            raise RuntimeError("the device is not running: call start() first")
        return self

    def _notify(self, sealed: bool) -> None:
        """From any thread: batches were sealed or dropped (`sealed`), or samples wait."""
        loop = self._loop
        if loop is None or self._closed:
            return
        if threading.get_ident() == self._loop_thread:
            self._kick(sealed)
        else:
            with contextlib.suppress(RuntimeError):  # the loop is closed
                loop.call_soon_threadsafe(self._kick, sealed)

    def _kick(self, sealed: bool) -> None:
        if self._work is None or self._pending is None:
            return
        if sealed:
            self._work.set()
            self._check_flush()
        else:
            self._pending.set()

    def _wake(self) -> None:
        if self._work is not None:
            self._work.set()

    def _answered(self, ack: Ack, count: int | None) -> None:
        """A batch was acknowledged or refused; `count` its samples if it was still held."""
        if count is not None:
            self.acked_samples += count
            # A duplicate was stored before, under an ack that was lost: the server counts
            # nothing as accepted now, but the samples are in history.
            accepted = count - ack.rejected_count if ack.duplicate else ack.accepted
            self.accepted_samples += accepted if ack.refused is None else 0
            self.server_timed_samples += ack.server_timed
            self.rejected += count if ack.refused is not None else ack.rejected_count
            self.duplicate_batches += ack.duplicate
            self.refused_batches += ack.refused is not None
        if ack.refused is not None:
            log.error("batch %d refused by the server: %s", ack.seq, ack.refused)
        elif ack.rejected_count:
            reasons = "; ".join(f"#{i}: {r}" for i, r in ack.rejected[:5])
            log.warning("batch %d: %d samples rejected (%s)", ack.seq, ack.rejected_count, reasons)
        assert self._space is not None and self._work is not None
        self._space.set()
        self._work.set()
        self._check_flush()
        if self.on_ack is not None:
            try:
                self.on_ack(ack)
            except Exception:
                log.exception("the on_ack hook failed")

    def _check_flush(self) -> None:
        waiting = []
        for target, fut in self._flush_waiters:
            if fut.done():
                continue
            if self._batcher.done_through(target):
                fut.set_result(None)
            else:
                waiting.append((target, fut))
        self._flush_waiters = waiting

    async def _flush_loop(self) -> None:
        """Seal waiting samples `flush_interval` seconds after the first of them arrived."""
        assert self._pending is not None
        while True:
            await self._pending.wait()
            await asyncio.sleep(self.flush_interval)
            self._pending.clear()
            self._batcher.seal_all()
