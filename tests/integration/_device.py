"""A device on the device WebSocket for tests: it records what the server sends and answers
commands with a function the test gives (docs/protocol.md)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import httpx
import orjson
from websockets.asyncio.client import ClientConnection, connect

from tests.conftest import Server
from tests.integration._util import apply, twin_doc, unique

Answer = Callable[[dict[str, Any]], dict[str, Any] | None]  # command -> result fields or None

WAIT_S = 15.0


def make_twin(
    server: Server, interface: dict[str, Any] | None = None, devices: tuple[str, ...] = ("rig",)
) -> tuple[str, dict[str, str]]:
    """A new twin with devices; the slug and each device's token."""
    slug = unique("cmd")
    extra = {"interface": interface} if interface else {}
    tokens = {}
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, **extra))
        for name in devices:
            r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": name})
            assert r.status_code == 201, r.text
            tokens[name] = r.json()["token"]
    return slug, tokens


def admin_client(server: Server) -> httpx.AsyncClient:
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    return httpx.AsyncClient(base_url=server.url, headers=headers, timeout=30)


def succeed_with_args(command: dict[str, Any]) -> dict[str, Any]:
    return {"status": "succeeded", "result": {"name": command["name"], "args": command["args"]}}


class FakeDevice:
    """`async with FakeDevice(server, token, answer) as device:` connects and reads until the
    block ends. Each command is answered `delivered`, then with `answer(command)` unless that
    is None (the device then never answers, so the command expires)."""

    def __init__(self, server: Server, token: str, answer: Answer | None = succeed_with_args):
        self.url = server.url.replace("http://", "ws://") + "/api/v1/device/ws"
        self.token = token
        self.answer = answer
        self.welcome: dict[str, Any] = {}
        self._inbox: asyncio.Queue[dict[str, Any]] = asyncio.Queue()
        self._ws: ClientConnection | None = None
        self._reader: asyncio.Task[None] | None = None

    async def __aenter__(self) -> FakeDevice:
        self._ws = await connect(
            self.url, additional_headers={"Authorization": f"Bearer {self.token}"}
        )
        try:
            self.welcome = orjson.loads(await asyncio.wait_for(self._ws.recv(), WAIT_S))
            assert self.welcome["type"] == "welcome", self.welcome
        except BaseException:
            await self._ws.close()
            raise
        self._reader = asyncio.create_task(self._read())
        return self

    async def __aexit__(self, *exc: object) -> None:
        assert self._ws is not None and self._reader is not None
        await self._ws.close()
        await asyncio.gather(self._reader, return_exceptions=True)

    async def send(self, message: dict[str, Any]) -> None:
        assert self._ws is not None
        await self._ws.send(orjson.dumps(message).decode())

    async def next(self, kind: str) -> dict[str, Any]:
        """The next message of type `kind` the server sent (others before it are dropped)."""
        while True:
            message = await asyncio.wait_for(self._inbox.get(), WAIT_S)
            if message.get("type") == kind:
                return message

    async def settle(self) -> None:
        """Wait until the server has handled everything sent so far: it reads a device's
        messages in order, so its `pong` comes after them."""
        await self.send({"type": "ping"})
        await self.next("pong")

    async def _read(self) -> None:
        assert self._ws is not None
        async for raw in self._ws:
            message = orjson.loads(raw)
            if message.get("type") == "command":
                await self.send({"type": "delivered", "id": message["id"]})
                reply = self.answer(message) if self.answer else None
                if reply is not None:
                    await self.send({"type": "result", "id": message["id"], **reply})
            await self._inbox.put(message)
