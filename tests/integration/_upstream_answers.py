"""What the test upstream answers below a realm, once a request has signed in (see
`_upstream.py`): echoes, downloads made on the fly, server-sent events, a service that hangs,
redirects, answers with cookies or hop-by-hop headers, and a WebSocket echo."""

from __future__ import annotations

import asyncio
import hashlib
import json
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

CHUNK = 1 << 20
WAIT_S = 30.0  # the longest any answer waits for the test (a failing test must not hang)


@dataclass(frozen=True)
class Seen:
    """One request as it reached the upstream."""

    kind: str  # http | websocket
    method: str
    raw_path: str
    query: str
    headers: list[tuple[str, str]]

    def header(self, name: str) -> list[str]:
        return [v for k, v in self.headers if k == name.lower()]


@dataclass(frozen=True)
class Call:
    """One signed-in request: `arg` is the path after `<realm>/<answer>/`."""

    scope: dict[str, Any]
    receive: Callable[[], Awaitable[dict[str, Any]]]
    send: Callable[[dict[str, Any]], Awaitable[None]]
    seen: Seen
    realm: str
    arg: str
    events: dict[str, asyncio.Event]  # SSE key -> released (set from the test's thread)
    ws_closes: list[int]  # close codes WebSocket clients sent


def block(index: int) -> bytes:
    """The `index`th MiB of every download: differs per chunk, so reordering shows."""
    return index.to_bytes(8, "big") * (CHUNK // 8)


def download_digest(size: int) -> str:
    digest = hashlib.sha256()
    for index, start in enumerate(range(0, size, CHUNK)):
        digest.update(block(index)[: min(CHUNK, size - start)])
    return digest.hexdigest()


async def echo(call: Call) -> None:
    digest, size = hashlib.sha256(), 0
    while True:
        message = await call.receive()
        if message["type"] == "http.disconnect":
            return
        digest.update(message.get("body", b""))
        size += len(message.get("body", b""))
        if not message.get("more_body", False):
            break
    seen = call.seen
    answer = {
        "method": seen.method,
        "path": seen.raw_path,
        "query": seen.query,
        "headers": seen.headers,
        "body_len": size,
        "body_sha256": digest.hexdigest(),
    }
    await send_json(call.send, 200, answer)


async def download(call: Call) -> None:
    size = int(call.arg)
    headers = [(b"content-type", b"application/octet-stream")]
    if "chunked=1" not in call.seen.query:
        headers.append((b"content-length", str(size).encode()))
    await call.send({"type": "http.response.start", "status": 200, "headers": headers})
    if call.seen.method != "HEAD":
        for index, start in enumerate(range(0, size, CHUNK)):
            chunk = block(index)[: min(CHUNK, size - start)]
            await call.send({"type": "http.response.body", "body": chunk, "more_body": True})
    await call.send({"type": "http.response.body", "body": b""})


async def events(call: Call) -> None:
    headers = [(b"content-type", b"text/event-stream"), (b"cache-control", b"no-cache")]
    await call.send({"type": "http.response.start", "status": 200, "headers": headers})
    first = {"type": "http.response.body", "body": b"data: first\n\n", "more_body": True}
    await call.send(first)
    try:
        await asyncio.wait_for(call.events.setdefault(call.arg, asyncio.Event()).wait(), WAIT_S)
        last = b"data: last\n\n"
    except TimeoutError:
        last = b"data: never released\n\n"
    await call.send({"type": "http.response.body", "body": last})


async def slow(call: Call) -> None:
    """A service that hangs: it answers only after WAIT_S, unless the client leaves first."""
    try:
        while (await asyncio.wait_for(call.receive(), WAIT_S))["type"] != "http.disconnect":
            pass
    except TimeoutError:
        await send_json(call.send, 200, {"late": True})


async def redirect(call: Call) -> None:
    host = dict(call.seen.headers).get("host", "")
    location = {
        "inside-absolute": f"http://{host}/{call.realm}/echo/landed?x=1",
        "inside-path": f"/{call.realm}/echo/landed",
        "relative": "echo/landed",
        "outside-host": "http://evil.example/steal",
        "outside-path": "/elsewhere/landed",
    }[call.arg]
    headers = [(b"location", location.encode()), (b"content-length", b"0")]
    await call.send({"type": "http.response.start", "status": 302, "headers": headers})
    await call.send({"type": "http.response.body", "body": b""})


async def cookie(call: Call) -> None:
    await send_json(call.send, 200, {}, [(b"set-cookie", b"upstream_session=abc; Path=/")])


async def hop(call: Call) -> None:
    extra = [
        (b"connection", b"x-hop-private"),
        (b"x-hop-private", b"1"),
        (b"keep-alive", b"timeout=5"),
        (b"x-end-to-end", b"kept"),
    ]
    await send_json(call.send, 200, {}, extra)


ANSWERS: dict[str, Callable[[Call], Awaitable[None]]] = {
    "bytes": download,
    "sse": events,
    "slow": slow,
    "redirect": redirect,
    "cookie": cookie,
    "hop": hop,
}


async def websocket_echo(call: Call) -> None:
    """Echo frames; a text `close:<code>:<reason>` closes with that code."""
    await call.send({"type": "websocket.accept"})
    while True:
        message = await call.receive()
        if message["type"] == "websocket.disconnect":
            call.ws_closes.append(int(message.get("code", 1000)))
            return
        text = message.get("text")
        if text is not None and text.startswith("close:"):
            _, code, reason = text.split(":", 2)
            await call.send({"type": "websocket.close", "code": int(code), "reason": reason})
            return
        if text is not None:
            await call.send({"type": "websocket.send", "text": text})
        else:
            await call.send({"type": "websocket.send", "bytes": message.get("bytes") or b""})


async def read_body(receive: Callable[[], Awaitable[dict[str, Any]]]) -> bytes:
    chunks = []
    while True:
        message = await receive()
        chunks.append(message.get("body", b""))
        if not message.get("more_body", False):
            return b"".join(chunks)


async def send_json(
    send: Callable[[dict[str, Any]], Awaitable[None]],
    status: int,
    body: Any,
    headers: list[tuple[bytes, bytes]] | None = None,
) -> None:
    data = json.dumps(body).encode()
    start = [(b"content-type", b"application/json"), (b"content-length", str(len(data)).encode())]
    message = {"type": "http.response.start", "status": status, "headers": start + (headers or [])}
    await send(message)
    await send({"type": "http.response.body", "body": data})
