"""Credentials that are a token fetched from a login endpoint (OAuth2, a custom login).

The token is kept until shortly before it expires and fetched again when the service
answers 401. Any number of requests refused at once cause one fetch: each says which token it
used, and only the first to ask for a refresh of that token performs it; the others share its
outcome, a failure included (a failing login endpoint is not called once per waiting request).

With a `share` (the gateway sets one when the nodes share a store), the token is also shared
between the nodes (shared.py): a node takes the stored token when it has none or another node
renewed it, and nodes refreshing together make one login between them.
"""

from __future__ import annotations

import asyncio
import logging
import math
import time
from typing import Any

import httpx

from twinlink.domain.errors import StorageError
from twinlink.gateway.credentials.base import C, Credentials, Headers, RefreshError, replace_header
from twinlink.gateway.credentials.shared import Held, TokenShare
from twinlink.gateway.headers import is_field_value

log = logging.getLogger("twinlink.gateway")

# A token is renewed this long (or 10% of its life, if less) before it expires.
EXPIRY_MARGIN_S = 10.0
LOGIN_TIMEOUT_S = 15.0
# How long a node waits for another node's login before it gives up on the shared token.
SHARED_WAIT_S = LOGIN_TIMEOUT_S + 5.0
DEFAULT_LIFE_S = 3600.0


class TokenCredentials(Credentials[C]):
    """A token fetched by `fetch` and sent as header `header_name`, formatted by `template`
    (`{token}` is replaced). Its `generation` counts the fetches that finished, whether they
    got a token or not."""

    can_refresh = True
    header_name = "Authorization"
    template = "Bearer {token}"

    def __init__(self, config: C) -> None:
        super().__init__(config)
        self._header: tuple[bytes, bytes] | None = None
        self._renew_at = 0.0
        self._expires_at = 0.0
        self._lock = asyncio.Lock()
        self.share: TokenShare | None = None  # set by the gateway when nodes share a store
        self._sealed: bytes | None = None  # the shared token this node holds, as stored

    async def fetch(self) -> tuple[str, float | None]:
        """A new token and its life in seconds (None: not said); RefreshError if none."""
        raise NotImplementedError

    def renewal_due(self) -> bool:
        """No token yet, or one past the time to renew it."""
        return self._header is None or time.monotonic() >= self._renew_at

    async def ready(self) -> int:
        if not self.renewal_due():
            return self.generation
        usable = self._header is not None and time.monotonic() < self._expires_at
        try:
            await self.refresh(self.generation)
        except RefreshError:
            if not usable:
                raise
            # The login endpoint failed in the renewal margin: the token still works a while.
        return self.generation

    def apply(self, headers: Headers, query: list[str]) -> None:
        if self._header is not None:
            replace_header(headers, self._header)

    async def refresh(self, refused_generation: int) -> None:
        async with self._lock:
            if self.generation != refused_generation:
                # A fetch finished while this request was out: share its outcome rather than
                # call the login endpoint again (and again, for each waiting request).
                if self.last_error is not None:
                    raise RefreshError(self.last_error)
                return
            try:
                if self.share is not None:
                    await self._refresh_shared(self.share)
                    return
                self._keep(*await self._login())
            except RefreshError as err:
                self.last_error = str(err)
                self.generation += 1
                raise

    async def _login(self) -> tuple[str, float, float]:
        """A new token: its header value, when to renew it and its life, in seconds."""
        token, expires_in = await self.fetch()
        value = self.template.replace("{token}", token)
        if not is_field_value(value):
            # A line break would end the header and could smuggle a request onto a
            # pooled connection; a character outside Latin-1 cannot be sent at all.
            raise RefreshError("the login endpoint sent a token that cannot go in a header")
        life = expires_in if expires_in and expires_in > 0 else DEFAULT_LIFE_S
        self.refreshes += 1
        return value, life - min(EXPIRY_MARGIN_S, life / 10), life

    async def _timed_login(self) -> tuple[str, float, float]:
        """A login the other nodes may be waiting for (SHARED_WAIT_S at most): it ends before
        they give up, not after each of its steps took LOGIN_TIMEOUT_S."""
        try:
            async with asyncio.timeout(LOGIN_TIMEOUT_S):
                return await self._login()
        except TimeoutError:
            raise RefreshError(
                f"the login endpoint did not answer within {LOGIN_TIMEOUT_S:g} s"
            ) from None

    async def _refresh_shared(self, share: TokenShare) -> None:
        """The stored token if it is another than this node's and not due; else one login
        among the nodes. Without the store (PostgreSQL away) this node logs in on its own."""
        try:
            held = await share.current()
            if held is None or held.sealed == self._sealed or held.renew_in_s <= 0:
                held = await share.refresh_once(self._sealed, self._timed_login, SHARED_WAIT_S)
        except StorageError as err:
            # Logging in alone may make the other nodes' tokens invalid (some upstreams keep
            # one token per client), but without it this service is down with the store.
            log.warning(
                "the gateway's shared token cannot be used (%s); this node logs in alone",
                err,
                extra={"event": "token_not_shared", "service": share.service},
            )
            self._keep(*await self._login())
            return
        self._adopt(held)

    def _adopt(self, held: Held) -> None:
        if held.expires_in_s <= 0:
            raise RefreshError("the shared token expired before this node could use it")
        self._sealed = held.sealed
        self._keep(held.value, held.renew_in_s, held.expires_in_s)

    def _keep(self, value: str, renew_in_s: float, expires_in_s: float) -> None:
        self._header = (self.header_name.lower().encode("latin-1"), value.encode("latin-1"))
        now = time.monotonic()
        self._expires_at = now + expires_in_s
        self._renew_at = now + renew_in_s
        self.generation += 1
        self.last_error = None

    async def post(self, url: str, **kwargs: Any) -> httpx.Response:
        try:
            async with httpx.AsyncClient(timeout=LOGIN_TIMEOUT_S, follow_redirects=False) as c:
                return await c.post(url, **kwargs)
        except httpx.HTTPError as err:
            # from None: the cause holds the login request, the service's credentials in it.
            raise RefreshError(
                f"the login endpoint {url} could not be reached: {type(err).__name__}"
            ) from None


def json_body(answer: httpx.Response) -> dict[str, Any]:
    """A login endpoint's answer as a JSON object; empty when it is none."""
    try:
        body = answer.json()
    except ValueError:
        return {}
    return body if isinstance(body, dict) else {}


def json_path(data: Any, path: str | None) -> Any:
    """`data.token` or `items.0.token` or `$.data.token` in a decoded JSON value."""
    if not path:
        return None
    for key in path.removeprefix("$").strip(".").split("."):
        if isinstance(data, dict):
            data = data.get(key)
        elif isinstance(data, list) and key.isdigit() and int(key) < len(data):
            data = data[int(key)]
        else:
            return None
    return data


def seconds(value: Any) -> float | None:
    """A login endpoint's `expires_in`, or None (renewed after the default hour) when it is
    not a finite number: `1e400` reads as infinity, a 400-digit integer overflows a float."""
    try:
        number = float(value) if value is not None else None
    except (TypeError, ValueError, OverflowError):
        return None
    return number if number is not None and math.isfinite(number) else None
