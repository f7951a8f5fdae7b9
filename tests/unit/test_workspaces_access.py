"""Who reaches a workspace: one-time tickets for one user's workspace, swapped for sessions
that end with the platform token they came from (workspaces/access.py), and what the proxy
reads from a request (workspaces/_asgi.py)."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthService
from twinlink.store.sqlite import SqliteStore
from twinlink.workspaces import _asgi, access
from twinlink.workspaces.access import Access
from twinlink.workspaces.proxy import _same_origin

PASSWORDS = {"alice": "pw-alice-123", "bob": "pw-bob-12345"}


@pytest.fixture
async def auth(tmp_path: Path) -> AsyncIterator[AuthService]:
    store = SqliteStore(tmp_path)
    await store.open()
    try:
        service = AuthService(store, session_ttl_s=3600)
        for username, password in PASSWORDS.items():
            await service.create_user(username, password, False, [])
        yield service
    finally:
        await store.close()


async def signed_in(auth: AuthService, username: str) -> Principal:
    issued = await auth.login(username, PASSWORDS[username])
    return await auth.authenticate(issued.token)


async def test_a_ticket_opens_its_users_workspace_once(auth: AuthService) -> None:
    gate = Access(auth.store)
    alice = await signed_in(auth, "alice")
    ticket = await gate.ticket(alice)
    assert gate.redeem(ticket, "bob") is None  # at another user's address: used up too
    ticket = await gate.ticket(alice)
    redeemed = gate.redeem(ticket, "alice")
    assert redeemed is not None
    session, grant = redeemed
    assert grant.username == "alice" and grant.expires_ns is not None  # a login's expiry
    assert gate.redeem(ticket, "alice") is None
    assert await gate.session(session, "alice") is not None
    assert await gate.session(session, "bob") is None
    assert await gate.session("made-up", "alice") is None


async def test_an_expired_ticket_opens_nothing(
    auth: AuthService, monkeypatch: pytest.MonkeyPatch
) -> None:
    gate = Access(auth.store)
    monkeypatch.setattr(access, "TICKET_TTL_S", -1.0)
    ticket = await gate.ticket(await signed_in(auth, "alice"))
    assert gate.redeem(ticket, "alice") is None


async def test_a_session_ends_with_its_login_and_with_the_workspace(
    auth: AuthService, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(access, "TOKEN_RECHECK_S", 0.0)
    gate = Access(auth.store)
    alice = await signed_in(auth, "alice")
    redeemed = gate.redeem(await gate.ticket(alice), "alice")
    assert redeemed is not None
    session = redeemed[0]
    assert alice.token_id is not None
    await auth.revoke_token(alice, alice.token_id)  # she logs out
    assert await gate.session(session, "alice") is None

    bob = await signed_in(auth, "bob")
    redeemed = gate.redeem(await gate.ticket(bob), "bob")
    assert redeemed is not None
    gate.end("bob")  # his workspace stopped
    assert await gate.session(redeemed[0], "bob") is None


def scope(headers: list[tuple[bytes, bytes]], query: bytes = b"") -> _asgi.Scope:
    return {"type": "http", "headers": headers, "query_string": query}


def test_the_proxys_cookie_stays_with_the_proxy() -> None:
    request = scope([(b"cookie", b"_xsrf=abc; twinlink_workspace=s3cret; username-x=y")])
    assert dict(_asgi.cookies(request))["twinlink_workspace"] == "s3cret"
    assert _asgi.cookie_header_without(request, "twinlink_workspace") == "_xsrf=abc; username-x=y"


def test_the_ticket_is_taken_out_of_the_query() -> None:
    assert _asgi.split_query(b"ticket=t1&reset=1", "ticket") == ("t1", "reset=1")
    assert _asgi.split_query(b"reset", "ticket") == (None, "reset=")


def test_only_jupyters_own_token_scheme_is_not_a_bearer() -> None:
    assert _asgi.bearer(scope([(b"authorization", b"Bearer tl_x")])) == "tl_x"
    assert _asgi.bearer(scope([(b"authorization", b"token jupyter")])) is None


@pytest.mark.parametrize(
    ("origin", "same"),
    [
        (None, True),  # no browser page: a script
        (b"http://twin.example:8000", True),
        (b"https://evil.example", False),
        (b"http://twin.example:9000", False),
        (b"null", False),
        (b"https://twins.example.org", True),  # the public URL, behind a reverse proxy
    ],
)
def test_a_change_must_come_from_the_servers_own_pages(origin: bytes | None, same: bool) -> None:
    headers = [(b"host", b"twin.example:8000")]
    if origin is not None:
        headers.append((b"origin", origin))
    assert _same_origin(scope(headers), "https://twins.example.org") is same
