"""WebSockets to a workspace (kernels, terminals): the same admission as HTTP, then frames
relayed both ways until either side closes; each frame counts as use of the workspace."""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Awaitable, Callable
from typing import Any

from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed, InvalidHandshake, InvalidStatus

from twinlink.auth.service import AuthError
from twinlink.domain.errors import ForbiddenError, NotFoundError, UnavailableError
from twinlink.tasks import until_first_done
from twinlink.workspaces import _asgi
from twinlink.workspaces._asgi import Receive, Scope, Send
from twinlink.workspaces.access import COOKIE
from twinlink.workspaces.service import Workspace

# The proxy's admission: (scope, username, changes) -> the running workspace, or a refusal.
Admit = Callable[[Scope, str, bool], Awaitable[Workspace]]
OPEN_TIMEOUT_S = 10.0
MAX_FRAME = 64 * 2**20  # a notebook's output with images may be large


async def forward_websocket(
    admit: Admit, scope: Scope, receive: Receive, send: Send, username: str
) -> None:
    await receive()  # websocket.connect
    try:
        ws = await admit(scope, username, True)  # a WebSocket to a kernel runs code
        upstream = await _open(scope, ws)
    except (AuthError, ForbiddenError, NotFoundError, UnavailableError) as err:
        await _asgi.deny_websocket(scope, send, err)
        return
    try:
        await send({"type": "websocket.accept", "subprotocol": upstream.subprotocol})
        await _relay(receive, send, upstream, ws)
    finally:
        await upstream.close()


async def _open(scope: Scope, ws: Workspace) -> ClientConnection:
    assert ws.process is not None
    path = (scope.get("raw_path") or scope["path"].encode()).decode("latin-1")
    query = scope["query_string"].decode("latin-1")
    uri = f"ws://127.0.0.1:{ws.process.port}{path}" + (f"?{query}" if query else "")
    headers = [("Authorization", f"token {ws.process.token}")]
    kept = _asgi.cookie_header_without(scope, COOKIE)
    if kept:
        headers.append(("Cookie", kept))
    offered = [
        p.strip()
        for name, value in scope["headers"]
        if name == b"sec-websocket-protocol"
        for p in value.decode("latin-1").split(",")
    ]
    try:
        return await connect(
            uri,
            additional_headers=headers,
            subprotocols=offered or None,
            open_timeout=OPEN_TIMEOUT_S,
            max_size=MAX_FRAME,
            compression=None,
            proxy=None,
        )
    except InvalidStatus as err:
        status = err.response.status_code
        if status == 404:
            raise NotFoundError(f"the workspace has nothing at {path}") from err
        raise UnavailableError(f"the workspace refused the WebSocket with {status}") from err
    except (OSError, TimeoutError, InvalidHandshake) as err:
        raise UnavailableError(
            f"the workspace could not be reached ({type(err).__name__}); stop it and start "
            "it again if this goes on"
        ) from err


async def _relay(receive: Receive, send: Send, upstream: ClientConnection, ws: Workspace) -> None:
    async def client_to_workspace() -> None:
        while True:
            message = await receive()
            if message["type"] == "websocket.disconnect":
                await upstream.close(message.get("code", 1000))
                return
            data: Any = message.get("text")
            if data is None:
                data = message.get("bytes") or b""
            ws.touch()
            await upstream.send(data)

    async def workspace_to_client() -> None:
        with contextlib.suppress(ConnectionClosed):
            async for data in upstream:
                ws.touch()
                key = "text" if isinstance(data, str) else "bytes"
                await send({"type": "websocket.send", key: data})
        with contextlib.suppress(Exception):  # the client may be gone already
            await send(
                {
                    "type": "websocket.close",
                    "code": upstream.close_code or 1000,
                    "reason": upstream.close_reason or "",
                }
            )

    tasks = [
        asyncio.create_task(client_to_workspace()),
        asyncio.create_task(workspace_to_client()),
    ]
    await until_first_done(tasks)
