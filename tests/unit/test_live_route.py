"""The live route's timers, with a stand-in WebSocket: a client that never authenticates is
refused when the auth time is up, and the token is checked again while a client is silent."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest

from tests.unit.test_live_session import FakeAuth, FakeRegistry
from twinlink.api import live as route
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError
from twinlink.bus import MemoryBus
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.session import LiveSession


class SilentSocket:
    """A client that sends nothing and never leaves."""

    def __init__(self, headers: dict[str, str] | None = None) -> None:
        self.headers = headers or {}
        self.never: asyncio.Future[Any] = asyncio.get_running_loop().create_future()

    async def receive(self) -> dict[str, Any]:
        return await self.never  # type: ignore[no-any-return]


async def test_a_client_that_does_not_authenticate_in_time_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(route, "AUTH_TIMEOUT_S", 0.05)
    with pytest.raises(AuthError, match="no token: send 'Authorization: Bearer <token>'"):
        await route._authenticate(SilentSocket(), FakeAuth())  # type: ignore[arg-type]


async def test_the_header_token_is_used_when_sent() -> None:
    socket = SilentSocket({"authorization": "Bearer tl_good"})
    token, principal = await route._authenticate(socket, FakeAuth())  # type: ignore[arg-type]
    assert token == "tl_good" and principal.user is not None


async def test_the_token_is_checked_again_while_the_client_is_silent(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(route, "RECHECK_S", 0.01)
    auth = FakeAuth()
    session = LiveSession(
        "tl_good",
        Principal(user=None),
        hub=LiveHub(MemoryBus()),
        outbox=Outbox(4),
        auth=auth,
        registry=FakeRegistry(),
    )
    serving = asyncio.create_task(route._serve(SilentSocket(), session))  # type: ignore[arg-type]
    # Wait (bounded) for a few checks to pass, then revoke: the connection must end with
    # AuthError (closed with 4401 by the caller of _serve).
    async with asyncio.timeout(5):
        while auth.calls < 3:
            await asyncio.sleep(0.01)
        auth.valid = False
        assert isinstance(await serving, AuthError)
