"""Tokens shared by the nodes of one store: the gateway's upstream tokens (OAuth2, a custom
login), so that N nodes whose token expires, or is refused, log in once between them rather
than N times (an upstream with a rate limit on logins, or one whose login revokes the token
it gave before, breaks with N logins at once).

A token is a service's (`service`: the gateway's twin and service) for one version of its
credentials (`fingerprint`): a row of another fingerprint is as good as none, so changed
credentials never reuse the token of the old ones. The value is sealed by the caller before
it reaches the store (the store never sees a token in the clear). Times are the store's
clock, never a node's, handed out as seconds from now.

Only the shared backend (PostgreSQL) has an implementation: the embedded store has one node,
whose credentials keep their token in memory as they always did.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import NamedTuple, Protocol

from twinlink.domain.errors import TwinlinkError


class SharedToken(NamedTuple):
    """A stored token: sealed, renewed by whoever uses it `renew_in_s` from now, unusable
    `expires_in_s` from now (both negative once past)."""

    sealed: bytes
    renew_in_s: float
    expires_in_s: float


class NewToken(NamedTuple):
    """What a login gives: the sealed token, when to renew it and its life, in seconds."""

    sealed: bytes
    renew_after_s: float
    life_s: float


class SharedRefreshFailed(TwinlinkError):
    """The login another node made while this one waited for it failed; the message is that
    node's (it never holds a secret)."""


# The login: a new token, or an error whose message is shared with the nodes that waited.
Fetch = Callable[[], Awaitable[NewToken]]


class SharedTokens(Protocol):
    async def current(self, service: str, fingerprint: str) -> SharedToken | None:
        """The stored token of `service` for credentials `fingerprint`; None if there is none
        (or only one of other credentials)."""
        ...

    async def refresh_once(
        self, service: str, fingerprint: str, stale: bytes | None, fetch: Fetch, wait_s: float
    ) -> SharedToken:
        """A token other than `stale` (the one refused or due, None: none held), from one
        login among all nodes: the first caller runs `fetch` and stores its token; callers
        waiting meanwhile (at most `wait_s`, then StorageError) take that token, or, when
        the login failed after they asked, get SharedRefreshFailed with its message. A
        TwinlinkError from `fetch` is recorded so and raised to its caller as it is."""
        ...
