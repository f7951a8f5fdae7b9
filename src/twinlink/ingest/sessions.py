"""Connected devices: one session per device, and the handlers other services plug in.

The device WebSocket handles `samples` and `ping` itself. Commands and properties register
handlers for the message types they own (`delivered`, `result`, `reported`) and hooks run when
a device connects (to deliver queued commands and the desired properties), so this module
knows nothing about them.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any, Protocol

import orjson

from twinlink.domain.records import Device

log = logging.getLogger("twinlink.devices")


class Transport(Protocol):
    async def send_text(self, data: str) -> None: ...

    async def close(self, code: int, reason: str) -> None: ...


class DeviceSession:
    """One connected device. `send` queues a message; a writer task puts it on the wire, so
    a device that reads slowly never blocks whoever sends to it. Until `open` sends the
    welcome, messages are held back, so the welcome is always the first message a device
    reads even when a command races the connection."""

    MAX_QUEUED = 10_000

    def __init__(self, device: Device, transport: Transport) -> None:
        self.device = device
        self.transport = transport
        self._queue: asyncio.Queue[str | None] = asyncio.Queue(self.MAX_QUEUED)
        self.closed = asyncio.Event()
        self._held: list[str] | None = []
        self._writer = asyncio.create_task(self._write(), name=f"device-{device.id}-writer")

    def send(self, message: dict[str, Any]) -> bool:
        """Queue `message` for the device; False when the session is closed or full."""
        if self.closed.is_set():
            return False
        text = orjson.dumps(message).decode()
        if self._held is not None:
            self._held.append(text)
            return True
        return self._put(text)

    def open(self, welcome: dict[str, Any]) -> None:
        """Send `welcome`, then whatever was sent before it."""
        held, self._held = self._held or [], None
        for text in (orjson.dumps(welcome).decode(), *held):
            self._put(text)

    def _put(self, text: str) -> bool:
        try:
            self._queue.put_nowait(text)
        except asyncio.QueueFull:
            log.warning("device queue full", extra={"event": "device_queue_full",
                                                    "device": self.device.name})  # fmt: skip
            return False
        return True

    async def _write(self) -> None:
        while (text := await self._queue.get()) is not None:
            try:
                await self.transport.send_text(text)
            except Exception:  # the socket went away; the reader notices and cleans up
                self.closed.set()
                return

    async def close(self, code: int = 1000, reason: str = "") -> None:
        if self.closed.is_set():
            return
        self.closed.set()
        self._writer.cancel()
        await asyncio.gather(self._writer, return_exceptions=True)
        try:
            await self.transport.close(code, reason)
        except Exception:  # already closed by the peer
            return


MessageHandler = Callable[[DeviceSession, dict[str, Any]], Awaitable[dict[str, Any] | None]]
ConnectHook = Callable[[DeviceSession], Awaitable[None]]


class DeviceHub:
    def __init__(self) -> None:
        self.sessions: dict[int, DeviceSession] = {}
        self.handlers: dict[str, MessageHandler] = {}
        self.connect_hooks: list[ConnectHook] = []
        self.welcome_extras: list[Callable[[Device], Awaitable[dict[str, Any]]]] = []

    def handle(self, message_type: str, handler: MessageHandler) -> None:
        self.handlers[message_type] = handler

    def on_connect(self, hook: ConnectHook) -> None:
        self.connect_hooks.append(hook)

    def session(self, device_id: int) -> DeviceSession | None:
        session = self.sessions.get(device_id)
        return None if session is None or session.closed.is_set() else session

    async def attach(self, session: DeviceSession) -> None:
        """Make `session` the device's session; an older connection of the same device is
        closed (code 4409), since commands must go to exactly one place."""
        old = self.sessions.get(session.device.id)
        self.sessions[session.device.id] = session
        if old is not None:
            await old.close(4409, "replaced by a newer connection of this device")

    def detach(self, session: DeviceSession) -> None:
        if self.sessions.get(session.device.id) is session:
            del self.sessions[session.device.id]

    async def welcome(self, device: Device) -> dict[str, Any]:
        extra: dict[str, Any] = {}
        for part in self.welcome_extras:
            extra.update(await part(device))
        return extra

    async def connected(self, session: DeviceSession) -> None:
        for hook in self.connect_hooks:
            try:
                await hook(session)
            except Exception:
                log.exception("device connect hook failed", extra={"event": "device_hook"})
