"""Who may reach a workspace through the proxy: one-time tickets, and the cookie sessions
they are swapped for.

A browser cannot send the platform's Bearer token on a page load, so the start answer carries
a ticket (in the URL, valid once, for TICKET_TTL_S); the proxy swaps it for an HttpOnly,
SameSite=Strict cookie scoped to `/workspaces/<user>/` that holds a random session id. The
map from that id to the user is kept here, in memory: a session lives as long as the platform
token the ticket was asked with (its login session), and at most as long as the workspace.
The token is checked again every TOKEN_RECHECK_S, so a logout or a revoked token ends the
workspace session too.
"""

from __future__ import annotations

import secrets
import time
from dataclasses import dataclass

from twinlink.auth.rights import Principal
from twinlink.store.base import MetadataStore

TICKET_TTL_S = 60.0
TOKEN_RECHECK_S = 30.0
COOKIE = "twinlink_workspace"


@dataclass(slots=True)
class Grant:
    """A ticket or a session: whose workspace it opens, and the platform token behind it."""

    user_id: int
    username: str
    token_id: int | None
    expires_ns: int | None  # the platform token's expiry (None: it has none)
    checked: float  # when the token was last found valid (monotonic s)


class Access:
    def __init__(self, store: MetadataStore) -> None:
        self.store = store
        self._tickets: dict[str, tuple[Grant, float]] = {}  # ticket -> grant, valid until
        self._sessions: dict[str, Grant] = {}

    async def ticket(self, principal: Principal) -> str:
        """A one-time ticket to the caller's own workspace."""
        assert principal.user is not None
        expires_ns = None
        if principal.token_id is not None:
            record = await self.store.get_token(principal.token_id)
            expires_ns = record.expires_ns if record is not None else None
        now = time.monotonic()
        self._tickets = {t: g for t, g in self._tickets.items() if g[1] > now}
        ticket = secrets.token_urlsafe(32)
        user = principal.user
        grant = Grant(user.id, user.username, principal.token_id, expires_ns, now)
        self._tickets[ticket] = (grant, now + TICKET_TTL_S)
        return ticket

    def redeem(self, ticket: str, username: str) -> tuple[str, Grant] | None:
        """The new session (id, grant) for a valid ticket to `username`'s workspace; the
        ticket is used up either way."""
        found = self._tickets.pop(ticket, None)
        if found is None or found[1] <= time.monotonic() or found[0].username != username:
            return None
        session = secrets.token_urlsafe(32)
        self._sessions[session] = found[0]
        return session, found[0]

    async def session(self, session: str, username: str) -> Grant | None:
        """The grant of a live session to `username`'s workspace, else None."""
        grant = self._sessions.get(session)
        if grant is None or grant.username != username:
            return None
        if grant.expires_ns is not None and grant.expires_ns <= time.time_ns():
            del self._sessions[session]
            return None
        now = time.monotonic()
        if grant.token_id is not None and now - grant.checked > TOKEN_RECHECK_S:
            record = await self.store.get_token(grant.token_id)
            if record is None or record.revoked_ns is not None:
                self._sessions.pop(session, None)
                return None
            grant.checked = now
        return grant

    def end(self, username: str) -> None:
        """No ticket or session to `username`'s workspace survives (it stopped)."""
        self._tickets = {t: g for t, g in self._tickets.items() if g[0].username != username}
        self._sessions = {s: g for s, g in self._sessions.items() if g.username != username}
