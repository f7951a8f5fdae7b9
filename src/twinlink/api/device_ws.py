"""The device side of the live data plane (docs/protocol.md): the device WebSocket and HTTP
ingest. A device token opens only these routes, and only for its own twin."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from fastapi import APIRouter, Request, WebSocket
from starlette.websockets import WebSocketDisconnect

from twinlink.api.devices import ThisDevice
from twinlink.api.models.problem import problems
from twinlink.api.models.system import BATCH_BODY, Ack
from twinlink.api.responses import JSONAnswer
from twinlink.auth.service import AuthError
from twinlink.domain.errors import DocumentTooLargeError, StorageError
from twinlink.domain.jsontext import JsonTextError, fits_int64, loads
from twinlink.domain.samples import BatchError, big_int_outside_samples
from twinlink.ingest.link import DeviceLink, connect_device, disconnect_device
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceSession
from twinlink.registry.devices import DeviceService

router = APIRouter(prefix="/api/v1", tags=["device"])
log = logging.getLogger("twinlink.ingest")

MAX_BATCH_BYTES = 16 * 1024 * 1024


def _bearer(headers: Any) -> str | None:
    value = headers.get("authorization", "")
    scheme, _, token = value.partition(" ")
    return token.strip() if scheme.lower() == "bearer" and token.strip() else None


@router.post(
    "/device/samples",
    summary="Send a batch of samples (device token); the answer is its ack",
    response_class=JSONAnswer,
    response_model=Ack,
    responses=problems(401, 413, 422, 503, 507),
    openapi_extra=BATCH_BODY,
)
async def post_samples(request: Request, device: ThisDevice) -> JSONAnswer:
    declared = request.headers.get("content-length")
    if declared is not None and declared.isdigit() and int(declared) > MAX_BATCH_BYTES:
        raise DocumentTooLargeError(f"A batch is at most {MAX_BATCH_BYTES} bytes.")
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BATCH_BYTES:
            raise DocumentTooLargeError(f"A batch is at most {MAX_BATCH_BYTES} bytes.")
    try:
        parsed = loads(body)  # integers exact: one beyond 64 bits is refused, not rounded
    except JsonTextError as err:
        raise BatchError(f"the body is not JSON: {err}") from err
    ingest: IngestService = request.app.state.services.ingest
    return JSONAnswer((await ingest.ingest(device, parsed)).message())


@router.websocket("/device/ws")
async def device_socket(websocket: WebSocket) -> None:
    services = websocket.app.state.services
    token = _bearer(websocket.headers)
    await websocket.accept()
    try:
        if token is None:
            raise AuthError("a device token is required (Authorization: Bearer tld_...)")
        device = await services.devices.authenticate(token)
    except AuthError as err:
        await websocket.close(code=4401, reason=str(err))
        return
    except StorageError as err:  # the token could not be read: say so, the device retries
        await websocket.close(code=1011, reason=str(err)[:120])
        return
    link = await connect_device(services.device_hub, services.ingest, device, websocket)
    recheck = asyncio.create_task(_recheck_token(link.session, services.devices, token))
    try:
        await _read(link, websocket)
    finally:
        recheck.cancel()
        await disconnect_device(link)


async def _recheck_token(session: DeviceSession, devices: DeviceService, token: str) -> None:
    """A token revoked or replaced (or a device deleted) while connected ends the connection
    (4401). So does a check that fails for another reason (1011): a connection whose token
    cannot be checked is not left open unchecked."""
    while not session.closed.is_set():
        await asyncio.sleep(devices.recheck_delay())
        try:
            await devices.authenticate(token)
        except AuthError as err:
            await session.close(4401, str(err))
        except Exception as err:
            log.warning("device token check failed; closing the connection: %s", err,
                        extra={"event": "device_recheck_failed",
                               "device": session.device.name})  # fmt: skip
            await session.close(1011, "the device token could not be checked again; reconnect")


async def _read(link: DeviceLink, websocket: WebSocket) -> None:
    while not link.session.closed.is_set():
        try:
            frame = await websocket.receive()
        except (WebSocketDisconnect, RuntimeError):
            return
        if frame["type"] == "websocket.disconnect":
            return
        raw = frame.get("text") or frame.get("bytes") or b""
        try:
            message = loads(raw)  # integers exact: one beyond 64 bits is refused, not rounded
        except JsonTextError as err:
            link.error(f"the message is not JSON: {err}")
            continue
        if not isinstance(message, dict):
            link.error("a message is a JSON object with a `type`")
            continue
        big = big_int_outside_samples(message)
        if big is not None:
            _refuse(link, message, big)
            continue
        await link.dispatch(message)


def _refuse(link: DeviceLink, message: dict[str, Any], text: str) -> None:
    """Answer a message refused before dispatch as `dispatch` answers its own refusals: a
    batch by its `seq`, any other message by its type and `id` (each only if it can be
    echoed: the number refused may be that one)."""
    kind, seq, ref = message.get("type"), message.get("seq"), message.get("id")
    if kind == "samples":
        link.error(text, seq=seq if _echoable(seq) else None)
    else:
        link.error(text, op=kind if isinstance(kind, str) else "",
                   ref=ref if _echoable(ref) else None)  # fmt: skip


def _echoable(value: Any) -> bool:
    return isinstance(value, str) or (type(value) is int and fits_int64(value))
