"""What the workspace proxy reads from a request and how it refuses one, in plain ASGI (it
runs in front of FastAPI, as the gateway does)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any
from urllib.parse import parse_qsl, urlencode

import orjson

from twinlink.domain.errors import TwinlinkError, problem_document

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]


def header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope["headers"]:
        if key == name:
            return str(value.decode("latin-1"))
    return None


def bearer(scope: Scope) -> str | None:
    """The platform token of `Authorization: Bearer ...` (JupyterLab's own pages send
    `Authorization: token ...`, which is theirs, not the platform's)."""
    value = header(scope, b"authorization")
    if value is None:
        return None
    scheme, _, token = value.partition(" ")
    return token.strip() if scheme.lower() == "bearer" else None


def cookies(scope: Scope) -> list[tuple[str, str]]:
    """The request's cookies, in order, as (name, value)."""
    found = []
    for key, value in scope["headers"]:
        if key == b"cookie":
            for part in value.decode("latin-1").split(";"):
                name, sep, text = part.strip().partition("=")
                if sep:
                    found.append((name, text))
    return found


def cookie_header_without(scope: Scope, name: str) -> str:
    """The Cookie header for the workspace: every cookie but the proxy's own."""
    return "; ".join(f"{k}={v}" for k, v in cookies(scope) if k != name)


def split_query(query: bytes, name: str) -> tuple[str | None, str]:
    """The value of `name` in the query string (None if absent) and the query without it."""
    pairs = parse_qsl(query.decode("latin-1"), keep_blank_values=True)
    value = next((v for k, v in pairs if k == name), None)
    return value, urlencode([(k, v) for k, v in pairs if k != name])


def problem(err: TwinlinkError) -> tuple[int, bytes, list[tuple[bytes, bytes]]]:
    body = orjson.dumps(problem_document(err))
    headers = [
        (b"content-type", b"application/problem+json"),
        (b"content-length", str(len(body)).encode()),
        (b"cache-control", b"no-store"),
    ]
    if err.status == 401:
        headers.append((b"www-authenticate", b'Bearer realm="twinlink"'))
    headers += [(k.lower().encode(), v.encode()) for k, v in err.problem_headers().items()]
    return err.status, body, headers


async def send_problem(send: Send, err: TwinlinkError) -> None:
    status, body, headers = problem(err)
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


async def deny_websocket(scope: Scope, send: Send, err: TwinlinkError) -> None:
    """Refuse a WebSocket handshake with the problem as an HTTP answer where the server
    allows it, else a close with a policy-violation code."""
    if "websocket.http.response" in scope.get("extensions", {}):
        status, body, headers = problem(err)
        await send({"type": "websocket.http.response.start", "status": status, "headers": headers})
        await send({"type": "websocket.http.response.body", "body": body})
        return
    await send({"type": "websocket.close", "code": 1008, "reason": str(err)[:120]})
