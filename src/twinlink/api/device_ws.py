"""The device side of the live data plane (docs/protocol.md): the device WebSocket and HTTP
ingest. A device token opens only these routes, and only for its own twin."""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

import orjson
from fastapi import APIRouter, Request, WebSocket
from starlette.websockets import WebSocketDisconnect

from twinlink.api.devices import ThisDevice
from twinlink.api.responses import JSONAnswer
from twinlink.auth.service import AuthError
from twinlink.domain.errors import DocumentTooLargeError
from twinlink.domain.samples import BatchError
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub, DeviceSession
from twinlink.store.records import Device

router = APIRouter(prefix="/api/v1", tags=["device"])
log = logging.getLogger("twinlink.ingest")

MAX_BATCH_BYTES = 16 * 1024 * 1024
MAX_IN_FLIGHT = 64  # batches of one connection being stored at once
RECHECK_TOKEN_S = 60.0


def _bearer(headers: Any) -> str | None:
    value = headers.get("authorization", "")
    scheme, _, token = value.partition(" ")
    return token.strip() if scheme.lower() == "bearer" and token.strip() else None


@router.post(
    "/device/samples",
    summary="Send a batch of samples (device token); the answer is its ack",
    response_class=JSONAnswer,
)
async def post_samples(request: Request, device: ThisDevice) -> dict[str, Any]:
    declared = request.headers.get("content-length")
    if declared is not None and declared.isdigit() and int(declared) > MAX_BATCH_BYTES:
        raise DocumentTooLargeError(f"A batch is at most {MAX_BATCH_BYTES} bytes.")
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BATCH_BYTES:
            raise DocumentTooLargeError(f"A batch is at most {MAX_BATCH_BYTES} bytes.")
    try:
        parsed = orjson.loads(body)
    except orjson.JSONDecodeError as err:
        raise BatchError(f"the body is not JSON: {err}") from None
    ingest: IngestService = request.app.state.services.ingest
    return (await ingest.ingest(device, parsed)).message()


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
    hub: DeviceHub = services.device_hub
    session = DeviceSession(device, websocket)
    await hub.attach(session)
    session.open(
        {
            "type": "welcome",
            "device": device.name,
            "twin": device.twin_slug,
            "server_time": time.time_ns(),
            **await hub.welcome(device),
        }
    )
    await hub.connected(session)
    log.info("device connected", extra={"event": "device_connected", "device": device.name,
                                        "twin": device.twin_slug})  # fmt: skip
    connection = _Connection(session, services.ingest, hub)
    recheck = asyncio.create_task(_recheck_token(session, services.devices, token))
    try:
        await connection.read(websocket)
    finally:
        recheck.cancel()
        hub.detach(session)
        await connection.finish()
        await session.close()
        log.info("device disconnected", extra={"event": "device_disconnected",
                                               "device": device.name})  # fmt: skip


async def _recheck_token(session: DeviceSession, devices: Any, token: str) -> None:
    """A token revoked (or a device deleted) while connected ends the connection."""
    while not session.closed.is_set():
        await asyncio.sleep(RECHECK_TOKEN_S)
        try:
            await devices.authenticate(token)
        except AuthError as err:
            await session.close(4401, str(err))


class _Connection:
    def __init__(self, session: DeviceSession, ingest: IngestService, hub: DeviceHub) -> None:
        self.session = session
        self.ingest = ingest
        self.hub = hub
        self.in_flight = asyncio.Semaphore(MAX_IN_FLIGHT)
        self.tasks: set[asyncio.Task[None]] = set()

    async def read(self, websocket: WebSocket) -> None:
        while not self.session.closed.is_set():
            try:
                frame = await websocket.receive()
            except (WebSocketDisconnect, RuntimeError):
                return
            if frame["type"] == "websocket.disconnect":
                return
            raw = frame.get("text") or frame.get("bytes") or b""
            try:
                message = orjson.loads(raw)
            except orjson.JSONDecodeError as err:
                self.error(f"the message is not JSON: {err}")
                continue
            if not isinstance(message, dict):
                self.error("a message is a JSON object with a `type`")
                continue
            await self.dispatch(message)

    async def dispatch(self, message: dict[str, Any]) -> None:
        kind = message.get("type")
        if kind == "samples":  # errors about a batch name it by `seq`
            # Storing runs beside reading, so batches that arrive together share a commit;
            # the semaphore stops reading when too many are waiting (back-pressure).
            await self.in_flight.acquire()
            task = asyncio.create_task(self.store(message))
            self.tasks.add(task)
            task.add_done_callback(self.tasks.discard)
        elif kind == "ping":
            self.session.send({"type": "pong", "server_time": time.time_ns()})
        elif isinstance(kind, str) and kind in self.hub.handlers:
            try:
                reply = await self.hub.handlers[kind](self.session, message)
            except ValueError as err:
                self.error(str(err), op=kind, ref=message.get("id"))
                return
            if reply is not None:
                self.session.send(reply)
        else:
            known = ", ".join(sorted({"samples", "ping", *self.hub.handlers}))
            self.error(f"unknown message type {kind!r}; expected one of {known}")

    async def store(self, message: dict[str, Any]) -> None:
        device: Device = self.session.device
        seq = message.get("seq")
        try:
            ack = await self.ingest.ingest(device, message)
        except BatchError as err:
            self.error(str(err), seq=seq)
        except Exception:
            log.exception("storing a batch failed", extra={"event": "ingest_failed"})
            self.error("the batch could not be stored; send it again", seq=seq, retry=True)
        else:
            self.session.send(ack.message())
        finally:
            self.in_flight.release()

    def error(
        self, text: str, seq: Any = None, retry: bool = False, op: str = "", ref: Any = None
    ) -> None:
        message: dict[str, Any] = {"type": "error", "message": text, "fatal": False}
        if op:  # the type of the message this answers, and its `id` when it had one
            message["op"] = op
            if isinstance(ref, str | int) and not isinstance(ref, bool):
                message["id"] = ref
        if isinstance(seq, int):
            message["seq"] = seq
        if retry:  # nothing wrong with the batch: a transient failure; resend it as it was
            message["retry"] = True
        self.session.send(message)

    async def finish(self) -> None:
        # Batches already being stored still land (the device resends them, unacked, and
        # the sequence number makes that harmless).
        if self.tasks:
            await asyncio.gather(*self.tasks, return_exceptions=True)
