"""WebSocket passthrough: the same checks as HTTP (a WebSocket can send, so it needs the
editor role), then frames are relayed both ways until either side closes.

Browsers cannot set headers on a WebSocket, so the gateway also takes its token from an
`access_token` query parameter here (removed before the request reaches the service).
"""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any

from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed, InvalidHandshake, InvalidStatus

from twinlink.auth.service import AuthService
from twinlink.gateway import paths
from twinlink.gateway.access import bearer, caller_of, resolve
from twinlink.gateway.exchange import (
    Exchange,
    GatewayProblem,
    Receive,
    Scope,
    Send,
    problem_body,
)
from twinlink.gateway.headers import request_headers
from twinlink.gateway.service import GatewayService
from twinlink.gateway.signin import renew, sign_in
from twinlink.gateway.table import Service
from twinlink.tasks import until_first_done

_HANDSHAKE = frozenset(
    {
        b"sec-websocket-key",
        b"sec-websocket-version",
        b"sec-websocket-extensions",
        b"sec-websocket-protocol",
        b"host",
        b"content-length",
    }
)


async def forward_websocket(
    gateway: GatewayService,
    auth: AuthService,
    scope: Scope,
    receive: Receive,
    send: Send,
    route: paths.Route,
) -> None:
    ex = Exchange("WEBSOCKET", "/" + route.rest.decode("latin-1"))
    ex.service, ex.twin = route.service, route.twin or gateway.default_twin or ""
    await receive()  # websocket.connect
    query, query_token = paths.strip_query_param(scope["query_string"], b"access_token")
    service: Service | None = None
    try:
        principal = await caller_of(auth, bearer(scope) or query_token, scope)
        ex.caller = principal.user.username if principal.user else "-"
        service = await resolve(gateway, principal, route, "editor")
        upstream = await _open(scope, route, service, query, ex)
    except GatewayProblem as problem:
        ex.status, ex.outcome = problem.status, problem.outcome
        await _deny(scope, send, problem)
        gateway.audit.record(ex.entry())
        return
    ex.status, ex.outcome = 101, "forwarded"
    try:
        await send({"type": "websocket.accept", "subprotocol": upstream.subprotocol})
        await _relay(receive, send, upstream, ex)
    finally:
        gateway.audit.record(ex.entry())


async def _open(
    scope: Scope, route: paths.Route, service: Service, query: bytes, ex: Exchange
) -> ClientConnection:
    if service.blocked or service.origin is None:
        raise GatewayProblem(503, f"the service {service.name!r} is not usable: {service.blocked}")
    if not service.settings.websocket:
        raise GatewayProblem(403, f"the service {service.name!r} does not take WebSockets")
    try:
        rest = paths.check_rest(route.rest)
    except paths.PathRefused as err:
        raise GatewayProblem(400, f"refused: {err}") from err
    offered = [
        p.strip()
        for name, value in scope["headers"]
        if name == b"sec-websocket-protocol"
        for p in value.decode("latin-1").split(",")
    ]
    for attempt in (0, 1):
        generation = await sign_in(service)
        headers, extra_query = _headers(scope, route, service), list[str]()
        service.credentials.apply(headers, extra_query)
        scheme = "wss" if service.origin.tls else "ws"
        host = service.host_header.decode()
        client_query = service.credentials.client_query(query)
        uri = f"{scheme}://{host}{paths.target(service.base_path, rest, client_query, extra_query)}"
        try:
            return await connect(
                uri,
                additional_headers=[(k.decode("latin-1"), v.decode("latin-1")) for k, v in headers],
                subprotocols=offered or None,
                open_timeout=service.settings.limits.connect_timeout_s,
                max_size=int(service.settings.limits.max_body_mb * 2**20),
                compression=None,
                proxy=None,
                ssl=service.origin.tls_context if service.origin.tls else None,
            )
        except InvalidStatus as err:
            status = err.response.status_code
            if status == 401 and attempt == 0:
                await renew(service, generation)
                continue
            raise GatewayProblem(
                502,
                f"the service {service.name!r} refused the WebSocket with {status}",
                outcome="upstream_refused",
            ) from err
        except (OSError, TimeoutError, InvalidHandshake) as err:
            raise GatewayProblem(
                502,
                f"the service {service.name!r} could not be reached: {type(err).__name__}",
                outcome="upstream_connect",
            ) from err
    raise GatewayProblem(502, "unreachable")  # pragma: no cover (the loop returns or raises)


def _headers(scope: Scope, route: paths.Route, service: Service) -> list[tuple[bytes, bytes]]:
    client = scope.get("client")
    host = next((v for k, v in scope["headers"] if k == b"host"), b"")
    shaped = request_headers(
        scope["headers"],
        service.host_header,
        client[0] if client else "",
        "https" if scope.get("scheme") == "wss" else "http",
        host,
        route.prefix,
    )
    return [(k, v) for k, v in shaped if k not in _HANDSHAKE]


async def _deny(scope: Scope, send: Send, problem: GatewayProblem) -> None:
    """Refuse the handshake with the problem as an HTTP answer where the server allows it."""
    if "websocket.http.response" in scope.get("extensions", {}):
        body, headers = problem_body(problem)
        await send(
            {"type": "websocket.http.response.start", "status": problem.status, "headers": headers}
        )
        await send({"type": "websocket.http.response.body", "body": body})
        return
    await send({"type": "websocket.close", "code": 1008, "reason": problem.detail[:120]})


async def _relay(receive: Receive, send: Send, upstream: ClientConnection, ex: Exchange) -> None:
    async def client_to_service() -> None:
        while True:
            message = await receive()
            if message["type"] == "websocket.disconnect":
                await upstream.close(message.get("code", 1000))
                return
            data: Any = message.get("text")
            if data is None:
                data = message.get("bytes") or b""
            ex.bytes_in += len(data)
            await upstream.send(data)

    async def service_to_client() -> None:
        try:
            async for data in upstream:
                ex.bytes_out += len(data)
                key = "text" if isinstance(data, str) else "bytes"
                await send({"type": "websocket.send", key: data})
        except ConnectionClosed:
            pass
        code = upstream.close_code or 1000
        with contextlib.suppress(Exception):  # the client may be gone already
            await send(
                {"type": "websocket.close", "code": code, "reason": upstream.close_reason or ""}
            )

    tasks = [asyncio.create_task(client_to_service()), asyncio.create_task(service_to_client())]
    try:
        await until_first_done(tasks)
    finally:
        await upstream.close()
