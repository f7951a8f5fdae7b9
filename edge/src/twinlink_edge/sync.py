"""`Device`: the same client for plain (synchronous) code. It runs an `AsyncDevice` on an event
loop in a background thread; `add` is called directly, everything else waits for the loop."""

from __future__ import annotations

import asyncio
import atexit
import logging
import threading
import weakref
from collections.abc import Coroutine
from concurrent.futures import TimeoutError as FutureTimeout
from typing import Any, Callable, TypeVar

from ._handlers import AnyCommandHandler, DesiredHandler
from ._protocol import JsonObject
from .aio import AsyncDevice

log = logging.getLogger("twinlink_edge")

F = TypeVar("F", bound=Callable[..., Any])
T = TypeVar("T")

_running: weakref.WeakSet[Device] = weakref.WeakSet()


@atexit.register
def _close_at_exit() -> None:
    """A program that never closes its device still sends what it added (for up to the
    device's `close_timeout`)."""
    for device in list(_running):
        try:
            device.close()
        except Exception:  # pragma: no cover - the interpreter is ending anyway
            log.exception("closing the device at exit failed")


class Device:
    """A device connected to twinlink, for synchronous code. Takes the arguments of
    `AsyncDevice`.

    ```python
    with Device("https://twins.example.org", token) as dev:
        dev.add({"temperature": 21.5})   # cheap: batched and sent by a background thread
        dev.flush(timeout=10)
    ```

    `add` blocks while the buffer is full (under `on_full="block"`). Handlers registered with
    `on_command` and `on_desired` run in a thread pool (plain functions) or on the background
    loop (coroutine functions)."""

    def __init__(self, url: str, token: str, **options: Any) -> None:
        self._dev = AsyncDevice(url, token, **options)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    # ---- lifecycle ---------------------------------------------------------------------

    def start(self) -> Device:
        """Start the background thread and begin connecting; returns at once."""
        with self._lock:
            if self._thread is not None:
                return self
            loop = asyncio.new_event_loop()
            thread = threading.Thread(
                target=self._serve, args=(loop,), name="twinlink-edge", daemon=True
            )
            thread.start()
            self._loop, self._thread = loop, thread
        self._call(self._dev.start())
        _running.add(self)
        return self

    @staticmethod
    def _serve(loop: asyncio.AbstractEventLoop) -> None:
        asyncio.set_event_loop(loop)
        try:
            loop.run_forever()
        finally:
            try:
                loop.run_until_complete(loop.shutdown_asyncgens())
                loop.run_until_complete(loop.shutdown_default_executor())
            except RuntimeError:  # at interpreter exit no thread may start: leave it be
                pass
            loop.close()

    def close(self, timeout: float | None = None) -> None:
        """Wait up to `timeout` (default `close_timeout`) seconds for outstanding acks, then
        disconnect and stop the background thread."""
        with self._lock:
            loop, thread = self._loop, self._thread
            self._loop = self._thread = None
        _running.discard(self)
        if loop is None or thread is None:
            self._dev._close_unstarted()
            return
        try:
            asyncio.run_coroutine_threadsafe(self._dev.close(timeout), loop).result()
        finally:
            loop.call_soon_threadsafe(loop.stop)
            thread.join()

    def __enter__(self) -> Device:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _call(self, coro: Coroutine[Any, Any, T], timeout: float | None = None) -> T:
        loop = self._loop
        if loop is None:
            coro.close()
            raise RuntimeError("the device is not running: call start() first")
        if threading.current_thread() is self._thread:
            coro.close()
            raise RuntimeError("a blocking Device call from its own event loop would deadlock")
        future = asyncio.run_coroutine_threadsafe(coro, loop)
        try:
            return future.result(timeout)
        except FutureTimeout:
            future.cancel()
            raise TimeoutError(f"no answer after {timeout} s") from None

    # ---- samples -----------------------------------------------------------------------

    def add(
        self, values: JsonObject, time_ns: int | None = None, stream: str | None = None
    ) -> None:
        """Queue one sample; blocks while the buffer is full under `on_full="block"`.
        `RuntimeError` before `start()`, as `flush` (nothing would ever send it)."""
        self._dev.add(values, time_ns, stream)

    send = add

    def flush(self, timeout: float | None = None) -> None:
        """Wait until every sample added so far is acknowledged; `TimeoutError` after
        `timeout` seconds."""
        self._call(self._dev.flush(timeout))

    # ---- commands and properties -------------------------------------------------------

    def on_command(self, name: str) -> Callable[[F], F]:
        return self._dev.on_command(name)

    def on_any_command(self, handler: AnyCommandHandler) -> AnyCommandHandler:
        return self._dev.on_any_command(handler)

    def on_desired(self, handler: DesiredHandler) -> DesiredHandler:
        loop = self._loop
        if loop is None or threading.current_thread() is self._thread:
            return self._dev.on_desired(handler)
        # On the loop, so that it is in order with the messages that call the handlers.
        asyncio.run_coroutine_threadsafe(self._register_desired(handler), loop).result()
        return handler

    async def _register_desired(self, handler: DesiredHandler) -> None:
        self._dev.on_desired(handler)

    def report(
        self, properties: JsonObject, *, wait: bool = True, timeout: float | None = None
    ) -> int | None:
        """Send reported properties; with `wait`, block until the server's version for them."""
        return self._call(self._dev.report(properties, wait=wait, timeout=timeout))

    def wait_connected(self, timeout: float | None = None) -> bool:
        return self._call(self._dev.wait_connected(timeout))

    # ---- state -------------------------------------------------------------------------

    @property
    def desired(self) -> JsonObject:
        return dict(self._dev.desired)

    @property
    def reported(self) -> JsonObject:
        return dict(self._dev.reported)

    @property
    def connected(self) -> bool:
        return self._dev.connected

    @property
    def acked_samples(self) -> int:
        return self._dev.acked_samples

    @property
    def rejected(self) -> int:
        return self._dev.rejected

    @property
    def buffered_samples(self) -> int:
        return self._dev.buffered_samples

    @property
    def device_name(self) -> str | None:
        return self._dev.device_name

    @property
    def last_error(self) -> str | None:
        """Why the last connection attempt failed or ended, as the SDK logged it."""
        return self._dev.last_error

    @property
    def aio(self) -> AsyncDevice:
        """The `AsyncDevice` underneath (its methods belong to the background loop)."""
        return self._dev

    def stats(self) -> dict[str, Any]:
        return self._dev.stats()
