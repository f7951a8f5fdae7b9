"""GET /api/v1/live: the WebSocket on which browsers and scripts watch streams live and send
commands (docs/protocol.md, "Live streams for clients").

Each connection runs three tasks. The reader acts on the client's messages one at a time (a
`command` op only starts there: it runs in a task of its own); the checker checks the token and
the subscriptions again every `RECHECK_S`, never while the reader is acting on a message (they
share a lock); the writer drains the connection's outbox into the socket. A slow socket blocks
only its own writer, so only its own outbox fills (and drops).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from fastapi import APIRouter, WebSocket
from starlette.websockets import WebSocketDisconnect

from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError
from twinlink.domain.errors import NotFoundError
from twinlink.live import protocol
from twinlink.live.outbox import Outbox
from twinlink.live.protocol import LiveMessageError
from twinlink.live.session import Authenticator, LatestReader, LiveSession
from twinlink.store.history import HistoryReadStore
from twinlink.tasks import until_first_done

router = APIRouter(prefix="/api/v1", tags=["live"])
log = logging.getLogger("twinlink.live")

AUTH_TIMEOUT_S = 10.0
RECHECK_S = 60.0
CLOSE_TIMEOUT_S = 5.0
CLOSE_UNAUTHORIZED = 4401
_MAX_REASON = 120  # a close reason is at most 123 bytes


class _Gone(Exception):
    """The client left before it was authenticated."""

    # Not a TwinlinkError: control flow of this route, which then just ends; nobody is left
    # to answer.


@router.websocket("/live")
async def live_socket(websocket: WebSocket) -> None:
    services = websocket.app.state.services
    await websocket.accept()
    try:
        token, principal = await _authenticate(websocket, services.auth)
    except AuthError as err:
        await _close(websocket, CLOSE_UNAUTHORIZED, str(err))
        return
    except _Gone:
        return
    assert principal.user is not None
    outbox = Outbox(websocket.app.state.settings.live_queue_messages)
    session = LiveSession(
        token,
        principal,
        hub=services.live,
        outbox=outbox,
        auth=services.auth,
        registry=services.registry,
        latest=_latest_reader(services.history),
        commands=services.commands,
    )
    outbox.put_control(protocol.welcome(principal.user.username, outbox.capacity))
    user = principal.user.username
    log.info("live client connected", extra={"event": "live_connected", "user": user})
    failure = await _serve(websocket, session)
    log.info(
        "live client disconnected",
        extra={"event": "live_disconnected", "user": user, "dropped": outbox.dropped_batches},
    )
    if isinstance(failure, AuthError):
        await _close(websocket, CLOSE_UNAUTHORIZED, str(failure))
    elif failure is not None:
        log.error("live connection failed", exc_info=failure, extra={"event": "live_failed"})
        await _close(websocket, 1011, "internal error")


async def _serve(websocket: WebSocket, session: LiveSession) -> BaseException | None:
    """Run reader, checker and writer until one ends; returns the exception that ended one,
    if any."""
    turn = asyncio.Lock()
    tasks = (
        asyncio.create_task(_read(websocket, session, turn)),
        asyncio.create_task(_check(session, turn)),
        asyncio.create_task(_write(websocket, session.outbox)),
    )
    try:
        return await until_first_done(tasks)
    finally:
        await session.stop_commands()
        session.close()


async def _authenticate(websocket: WebSocket, auth: Authenticator) -> tuple[str, Principal]:
    """The token (from the header, else from a first `auth` message) and its principal."""
    header = websocket.headers.get("authorization")
    if header is not None:
        scheme, _, token = header.partition(" ")
        if scheme.lower() != "bearer" or not token.strip():
            raise AuthError("the Authorization header must be 'Bearer <token>'")
        token = token.strip()
    else:
        token = await _first_message_token(websocket)
    return token, await auth.authenticate(token)


async def _first_message_token(websocket: WebSocket) -> str:
    try:
        frame = await asyncio.wait_for(websocket.receive(), AUTH_TIMEOUT_S)
    except TimeoutError as err:
        raise AuthError(
            f"no token: send 'Authorization: Bearer <token>' or an auth message "
            f"within {AUTH_TIMEOUT_S:g} s"
        ) from err
    if frame["type"] == "websocket.disconnect":
        raise _Gone
    try:
        return protocol.read_token(protocol.read_message(_payload(frame)))
    except LiveMessageError as err:
        raise AuthError(str(err)) from err


async def _read(websocket: WebSocket, session: LiveSession, turn: asyncio.Lock) -> None:
    while True:
        # Back-pressure: a client that does not read its answers is not read either.
        await session.outbox.control_room()
        frame = await websocket.receive()
        if frame["type"] == "websocket.disconnect":
            return
        async with turn:
            await session.handle(_payload(frame))


async def _check(session: LiveSession, turn: asyncio.Lock) -> None:
    """Check the token and the subscriptions again every RECHECK_S, also while the client is
    silent; AuthError ends the connection."""
    while True:
        await asyncio.sleep(RECHECK_S)
        async with turn:
            await session.recheck()


async def _write(websocket: WebSocket, outbox: Outbox) -> None:
    try:
        while True:
            message = await outbox.next_message()
            await websocket.send_text(message.decode())
    except WebSocketDisconnect:
        return


def _payload(frame: Any) -> str | bytes:
    text = frame.get("text")
    return text if text is not None else frame.get("bytes") or b""


async def _close(websocket: WebSocket, code: int, reason: str) -> None:
    if len(reason.encode()) > _MAX_REASON:
        reason = reason.encode()[: _MAX_REASON - 3].decode(errors="ignore") + "..."
    # A client that does not read may never let the close frame out: do not wait forever.
    with contextlib.suppress(TimeoutError, WebSocketDisconnect, RuntimeError):
        await asyncio.wait_for(websocket.close(code, reason), CLOSE_TIMEOUT_S)


def _latest_reader(history: HistoryReadStore) -> LatestReader:
    """The newest stored value of each subscribed signal, `{signal: {time, value}}`. A stream
    or signal with no history yet is no error here: its data may be about to arrive."""

    async def read(
        twin_id: int, stream: str, signals: frozenset[str] | None
    ) -> dict[str, dict[str, Any]]:
        try:
            found = await history.latest(twin_id, stream, None)
        except NotFoundError:
            return {}
        if signals is None:
            return found
        return {name: value for name, value in found.items() if name in signals}

    return read
