"""A small HTTP/1.1 client for the gateway's hot path: pooled keep-alive connections, bodies
streamed both ways with back-pressure, responses parsed by httptools (uvicorn's parser).

Why not aiohttp or httpx: forwarding a small request cost 210 us of client CPU with aiohttp
and 1.9 ms with httpx on this machine, against a budget of 500 us for the whole gateway
(docs/decisions/0006-gateway.md). This client does one thing: send a request that is already
checked and shaped by the proxy, and hand back the status, headers and body chunks.
"""

from __future__ import annotations

import asyncio
import collections
import ssl
import time
from collections.abc import AsyncIterator
from dataclasses import dataclass
from typing import cast

import httptools

from twinlink.domain.errors import TwinlinkError

Headers = list[tuple[bytes, bytes]]
# A response body is read from the socket ahead of the client by at most this much.
HIGH_WATER = 1 << 20
IDLE_KEEP_S = 30.0
IDLE_PER_ORIGIN = 128


class UpstreamError(TwinlinkError):
    """The service could not be reached or broke the exchange; `stage` says when."""

    def __init__(self, stage: str, detail: str) -> None:
        super().__init__(f"{stage}: {detail}")
        self.stage = stage  # connect | send | timeout | response
        self.detail = detail


@dataclass(frozen=True, slots=True)
class Origin:
    scheme: str
    host: str
    port: int
    # The service's TLS settings (https only); part of the key, so connections made with
    # other settings are never reused for it.
    tls_context: ssl.SSLContext | None = None

    @property
    def tls(self) -> bool:
        return self.scheme == "https"


class _Connection(asyncio.Protocol):
    """One keep-alive connection; serves one exchange at a time."""

    def __init__(self, origin: Origin) -> None:
        self.origin = origin
        self.transport: asyncio.Transport | None = None
        self.parser = httptools.HttpResponseParser(self)
        self.lost = False
        self.idle_since = 0.0
        self._head: asyncio.Future[None] | None = None
        self._headers: Headers = []
        self._chunks: collections.deque[bytes] = collections.deque()
        self._buffered = 0
        self._done = False
        self._error: UpstreamError | None = None
        self._waiter: asyncio.Future[None] | None = None
        self._can_write = asyncio.Event()
        self._can_write.set()
        self._paused = False
        self.head_only = False
        self.reusable = False
        self.received_any = False
        self._length: int | None = None  # a body of known length, not yet handed over raw
        self._body_seen = 0
        self._raw_left = 0
        self._keep_alive = False
        self._fresh_parser = False

    # -- asyncio.Protocol ------------------------------------------------------------------
    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # uvloop's transports are not asyncio.Transport subclasses, but behave as one.
        self.transport = cast(asyncio.Transport, transport)

    def data_received(self, data: bytes) -> None:
        self.received_any = True
        if self._raw_left:
            self._raw_body(data)
            return
        try:
            self.parser.feed_data(data)
        except httptools.HttpParserError as err:
            self._fail(UpstreamError("response", f"the service sent invalid HTTP: {err}"))
            self._close()
            return
        if self._length is not None and not self._done and self._error is None:
            # The rest of a body of known length needs no parsing: hand over what arrives.
            # (Parsing copied each piece once more and was a third of a large answer's CPU.)
            self._raw_left = self._length - self._body_seen
            self._length = None
            self._fresh_parser = True

    def _raw_body(self, data: bytes) -> None:
        if len(data) > self._raw_left:  # bytes after the answer: the service broke HTTP
            data, self._keep_alive = data[: self._raw_left], False
        self._raw_left -= len(data)
        self.on_body(data)
        if not self._raw_left:
            self._done = True
            self.reusable = self._keep_alive
            self._wake()

    def connection_lost(self, exc: Exception | None) -> None:
        self.lost = True
        self._can_write.set()
        if not self._done:
            self._fail(UpstreamError("response", "the service closed the connection"))

    def pause_writing(self) -> None:
        self._can_write.clear()

    def resume_writing(self) -> None:
        self._can_write.set()

    # -- httptools callbacks ---------------------------------------------------------------
    def on_header(self, name: bytes, value: bytes) -> None:
        self._headers.append((name, value))

    def on_headers_complete(self) -> None:
        if self._head is not None and not self._head.done():
            self._head.set_result(None)
        self._keep_alive = self.parser.should_keep_alive()
        self._length = _fixed_length(self._headers)
        if self.head_only:  # a HEAD answer has no body whatever its headers say
            self.on_message_complete()
            self._close()

    def on_body(self, body: bytes) -> None:
        self._body_seen += len(body)
        self._chunks.append(body)
        self._buffered += len(body)
        if self._buffered > HIGH_WATER and not self._paused and self.transport is not None:
            self._paused = True
            self.transport.pause_reading()
        self._wake()

    def on_message_complete(self) -> None:
        if self._done:
            return
        self._done = True
        self.reusable = not self.head_only and self.parser.should_keep_alive()
        self._wake()

    # -- used by the pool ------------------------------------------------------------------
    def _fail(self, error: UpstreamError) -> None:
        self._error = error
        if self._head is not None and not self._head.done():
            self._head.set_exception(error)
        self._wake()

    def _close(self) -> None:
        if self.transport is not None:
            self.transport.close()

    def begin(self, head_only: bool) -> None:
        self._head = asyncio.get_running_loop().create_future()
        self._headers = []
        self._chunks.clear()
        self._buffered = 0
        self._done = False
        self._error = None
        self.head_only = head_only
        self.reusable = False
        self.received_any = False
        self._length = None
        self._body_seen = 0
        self._raw_left = 0
        if self._fresh_parser:  # the last answer's body bypassed the parser
            self.parser = httptools.HttpResponseParser(self)
            self._fresh_parser = False

    async def write(self, data: bytes, *more: bytes) -> None:
        """Send `data` (and `more`, without joining them first); wait while the service
        reads slower than we write."""
        if self.lost or self.transport is None:
            raise UpstreamError("send", "the service closed the connection")
        if more:
            self.transport.writelines((data, *more))
        else:
            self.transport.write(data)
        if not self._can_write.is_set():
            await self._can_write.wait()

    async def head(self, timeout_s: float) -> tuple[int, Headers]:
        head = self._head
        assert head is not None
        if not head.done():
            # A timer, not asyncio.wait_for: this runs on every request, and wait_for's
            # task and shield cost more than the rest of the exchange's bookkeeping.
            timer = asyncio.get_running_loop().call_later(timeout_s, self._timed_out, head)
            try:
                await head
            finally:
                timer.cancel()
        else:
            head.result()  # raises the stored error, if any
        return self.parser.get_status_code(), self._headers

    def _timed_out(self, head: asyncio.Future[None]) -> None:
        if not head.done():
            head.set_exception(UpstreamError("timeout", "no answer in time"))
            self._close()

    def whole_body(self) -> bytes | None:
        """The whole body when the answer has fully arrived already, else None."""
        if not self._done or self._error is not None:
            return None
        whole = b"".join(self._chunks)
        self._chunks.clear()
        self._buffered = 0
        return whole

    async def body(self, timeout_s: float) -> AsyncIterator[bytes]:
        """The body in pieces as they arrive. Pieces are not joined: joining a large body's
        pieces cost more (allocating and copying megabytes) than one send per piece."""
        loop = asyncio.get_running_loop()
        chunks = self._chunks
        while True:
            if chunks:
                chunk = chunks.popleft()
                self._buffered -= len(chunk)
                if self._paused and self._buffered <= HIGH_WATER // 2 and self.transport:
                    self._paused = False
                    self.transport.resume_reading()
                yield chunk
                continue
            if self._done:
                return
            if self._error is not None:
                raise self._error
            waiter: asyncio.Future[None] = loop.create_future()
            self._waiter = waiter
            timer = loop.call_later(timeout_s, self._stalled, waiter, timeout_s)
            try:
                await waiter
            finally:
                timer.cancel()
                self._waiter = None

    def _stalled(self, waiter: asyncio.Future[None], timeout_s: float) -> None:
        if not waiter.done():
            waiter.set_exception(UpstreamError("timeout", f"the body stalled for {timeout_s:g} s"))
            self._close()

    def _wake(self) -> None:
        if self._waiter is not None and not self._waiter.done():
            self._waiter.set_result(None)


def _fixed_length(headers: Headers) -> int | None:
    """The Content-Length of an answer without Transfer-Encoding, else None."""
    length = None
    for name, value in headers:
        lower = name.lower()
        if lower == b"transfer-encoding":
            return None
        if lower == b"content-length":
            try:
                length = int(value)
            except ValueError:
                return None
    return length


class Pool:
    """Idle keep-alive connections per origin, newest first."""

    def __init__(self) -> None:
        self._idle: dict[Origin, list[_Connection]] = {}
        self.opened = 0

    async def connect(self, origin: Origin, timeout_s: float) -> tuple[_Connection, bool]:
        """A connection to `origin` and whether it was reused from the pool."""
        idle = self._idle.get(origin)
        now = time.monotonic()
        while idle:
            conn = idle.pop()
            if not conn.lost and now - conn.idle_since < IDLE_KEEP_S:
                return conn, True
            conn._close()
        loop = asyncio.get_running_loop()
        try:
            _, conn = await asyncio.wait_for(
                loop.create_connection(
                    lambda: _Connection(origin),
                    origin.host,
                    origin.port,
                    ssl=(origin.tls_context or ssl.create_default_context())
                    if origin.tls
                    else None,
                ),
                timeout_s,
            )
        except TimeoutError as err:
            raise UpstreamError("connect", f"no connection within {timeout_s:g} s") from err
        except (OSError, ssl.SSLError) as err:
            raise UpstreamError("connect", err.strerror or str(err)) from err
        self.opened += 1
        return conn, False

    def release(self, conn: _Connection) -> None:
        if conn.lost or not conn.reusable:
            conn._close()
            return
        idle = self._idle.setdefault(conn.origin, [])
        if len(idle) >= IDLE_PER_ORIGIN:
            conn._close()
            return
        conn.idle_since = time.monotonic()
        idle.append(conn)

    def prune(self) -> None:
        """Close connections idle longer than IDLE_KEEP_S, of every origin."""
        limit = time.monotonic() - IDLE_KEEP_S
        for origin, idle in list(self._idle.items()):
            for conn in [c for c in idle if c.lost or c.idle_since < limit]:
                idle.remove(conn)
                conn._close()
            if not idle:
                del self._idle[origin]

    def discard(self, conn: _Connection) -> None:
        conn._close()

    def close(self) -> None:
        for idle in self._idle.values():
            for conn in idle:
                conn._close()
        self._idle.clear()


def request_head(method: str, target: str, headers: Headers) -> bytes:
    lines = [f"{method} {target} HTTP/1.1\r\n".encode("latin-1")]
    lines.extend(name + b": " + value + b"\r\n" for name, value in headers)
    lines.append(b"\r\n")
    return b"".join(lines)
