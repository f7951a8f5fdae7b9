"""Sending one request to a service and streaming its answer back to the client."""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

from twinlink.gateway import paths
from twinlink.gateway.exchange import Exchange, GatewayProblem, Receive, Scope, Send
from twinlink.gateway.headers import (
    RedirectRefused,
    content_length,
    request_headers,
    response_headers,
)
from twinlink.gateway.table import Service
from twinlink.gateway.upstream import Headers, Pool, UpstreamError, _Connection, request_head

log = logging.getLogger("twinlink.gateway")
# Responses at least this large (or of unknown length) are watched for the client leaving,
# so a download nobody reads any more stops being fetched.
WATCH_FROM = 1 << 20
# A refused (401) answer's body is read and dropped up to this size to keep the connection.
DRAIN_LIMIT = 1 << 16
_BODY_METHODS = frozenset({"POST", "PUT", "PATCH"})


def _failure(service: Service, err: UpstreamError) -> GatewayProblem:
    if err.stage == "timeout":
        return GatewayProblem(
            504,
            f"the service {service.name!r} did not answer in time: {err.detail}",
            outcome="timeout",
        )
    return GatewayProblem(
        502,
        f"the service {service.name!r} could not be reached: {err.detail}",
        outcome=f"upstream_{err.stage}",
    )


class Sender:
    def __init__(
        self,
        pool: Pool,
        scope: Scope,
        receive: Receive,
        route: paths.Route,
        service: Service,
        rest: bytes,
        limit: int,
        ex: Exchange,
    ) -> None:
        self.pool = pool
        self.scope = scope
        self.receive = receive
        self.route = route
        self.service = service
        self.rest = rest
        self.limit = limit
        self.ex = ex
        self.method: str = scope["method"]
        client = scope.get("client")
        host = next((v for k, v in scope["headers"] if k == b"host"), b"")
        self.declared = content_length(scope["headers"])
        self.headers = [
            h
            for h in request_headers(
                scope["headers"],
                service.host_header,
                client[0] if client else "",
                scope.get("scheme", "http"),
                host,
                route.prefix,
            )
            if h[0] != b"content-length"
        ]

    async def send(self, body: list[bytes], more: bool) -> tuple[_Connection, int, Headers]:
        service = self.service
        assert service.origin is not None
        headers, query = list(self.headers), list[str]()
        service.credentials.apply(headers, query)
        chunked = more and self.declared is None
        if chunked:
            headers.append((b"transfer-encoding", b"chunked"))
        elif more and self.declared is not None:
            headers.append((b"content-length", str(self.declared).encode()))
        elif (size := sum(map(len, body))) or self.method in _BODY_METHODS:
            headers.append((b"content-length", str(size).encode()))
        client_query = service.credentials.client_query(self.scope["query_string"])
        target = paths.target(service.base_path, self.rest, client_query, query)
        head = request_head(self.method, target, headers)
        first = _framed(body) if chunked and any(body) else body
        limits = service.settings.limits
        started = time.perf_counter()
        for attempt in (0, 1):
            conn, reused = await self._connect(limits.connect_timeout_s)
            conn.begin(head_only=self.method == "HEAD")
            try:
                await conn.write(head, *first)
                if more:
                    await self._stream_rest(conn, chunked)
                status, answer = await conn.head(limits.timeout_s)
                break
            except UpstreamError as err:
                self.pool.discard(conn)
                # A kept-alive connection the service closed meanwhile: try a fresh one.
                if attempt == 0 and reused and not more and not conn.received_any:
                    continue
                raise _failure(service, err) from err
        self.ex.upstream_s = time.perf_counter() - started
        return conn, status, answer

    async def _connect(self, timeout_s: float) -> tuple[_Connection, bool]:
        assert self.service.origin is not None
        try:
            return await self.pool.connect(self.service.origin, timeout_s)
        except UpstreamError as err:
            raise _failure(self.service, err) from err

    async def _stream_rest(self, conn: _Connection, chunked: bool) -> None:
        while True:
            message = await self.receive()
            if message["type"] == "http.disconnect":
                self.pool.discard(conn)
                raise GatewayProblem(499, "the client went away", "client_left", sent=True)
            chunk = message.get("body", b"")
            self.ex.bytes_in += len(chunk)
            if self.ex.bytes_in > self.limit:
                self.pool.discard(conn)
                raise GatewayProblem(413, "the request body is over the service's size limit")
            if chunk:
                await conn.write(*(_framed([chunk]) if chunked else [chunk]))
            if not message.get("more_body", False):
                break
        if chunked:
            await conn.write(b"0\r\n\r\n")

    async def drain(self, conn: _Connection) -> None:
        """Read and drop a refused answer's body, keeping the connection when it is small."""
        size = 0
        try:
            async for chunk in conn.body(self.service.settings.limits.timeout_s):
                size += len(chunk)
                if size > DRAIN_LIMIT:
                    self.pool.discard(conn)
                    return
        except UpstreamError:
            self.pool.discard(conn)
            return
        self.pool.release(conn)

    async def respond(self, send: Send, conn: _Connection, status: int, raw: Headers) -> None:
        service, ex = self.service, self.ex
        try:
            headers = response_headers(raw, service.base_url or "", self.route.prefix)
        except RedirectRefused as err:
            self.pool.discard(conn)
            raise GatewayProblem(502, f"refused: {err}", outcome="redirect_refused") from err
        ex.status, ex.outcome = status, "forwarded"
        whole = conn.whole_body()
        if whole is not None:  # the usual small answer: already here, one send
            await send({"type": "http.response.start", "status": status, "headers": headers})
            await send({"type": "http.response.body", "body": whole})
            ex.bytes_out = len(whole)
            self.pool.release(conn)
            return
        declared = content_length(raw)
        watch = None
        if declared is None or declared >= WATCH_FROM:
            watch = asyncio.ensure_future(self.receive())
        await send({"type": "http.response.start", "status": status, "headers": headers})
        try:
            await self._stream_answer(send, conn, watch)
        finally:
            if watch is not None:
                watch.cancel()
        await send({"type": "http.response.body", "body": b""})
        self.pool.release(conn)

    async def _stream_answer(
        self, send: Send, conn: _Connection, watch: asyncio.Future[Any] | None
    ) -> None:
        try:
            async for chunk in conn.body(self.service.settings.limits.timeout_s):
                if watch is not None and watch.done():
                    self.pool.discard(conn)
                    raise GatewayProblem(499, "the client went away", "client_left", sent=True)
                await send({"type": "http.response.body", "body": chunk, "more_body": True})
                self.ex.bytes_out += len(chunk)
        except UpstreamError as err:
            self.pool.discard(conn)
            log.warning(
                "service answer broken off",
                extra={"event": "gateway_broken", "service": self.service.name, "error": str(err)},
            )
            outcome = f"upstream_{err.stage}"
            raise GatewayProblem(502, str(err), outcome=outcome, sent=True) from err


def _framed(pieces: list[bytes]) -> list[bytes]:
    """`pieces` as one chunk of chunked transfer coding, without copying them."""
    return [b"%x\r\n" % sum(map(len, pieces)), *pieces, b"\r\n"]
