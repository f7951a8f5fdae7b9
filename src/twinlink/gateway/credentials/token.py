"""Credentials that are a token fetched from a login endpoint (OAuth2, a custom login).

The token is kept until shortly before it expires and fetched again when the service
answers 401. Any number of requests refused at once cause one fetch: each says which token it
used, and only the first to ask for a refresh of that token performs it; the others share its
outcome, a failure included (a failing login endpoint is not called once per waiting request).
"""

from __future__ import annotations

import asyncio
import math
import time
from typing import Any

import httpx

from twinlink.gateway.credentials.base import C, Credentials, Headers, RefreshError, replace_header
from twinlink.gateway.headers import is_field_value

# A token is renewed this long (or 10% of its life, if less) before it expires.
EXPIRY_MARGIN_S = 10.0
LOGIN_TIMEOUT_S = 15.0


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

    async def fetch(self) -> tuple[str, float | None]:
        """A new token and its life in seconds (None: not said); RefreshError if none."""
        raise NotImplementedError

    async def ready(self) -> int:
        now = time.monotonic()
        if self._header is not None and now < self._renew_at:
            return self.generation
        usable = self._header is not None and now < self._expires_at
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
                token, expires_in = await self.fetch()
                value = self.template.replace("{token}", token)
                if not is_field_value(value):
                    # A line break would end the header and could smuggle a request onto a
                    # pooled connection; a character outside Latin-1 cannot be sent at all.
                    raise RefreshError("the login endpoint sent a token that cannot go in a header")
            except RefreshError as err:
                self.last_error = str(err)
                self.generation += 1
                raise
            self._keep(value, expires_in)

    def _keep(self, value: str, expires_in: float | None) -> None:
        self._header = (self.header_name.lower().encode("latin-1"), value.encode("latin-1"))
        life = expires_in if expires_in and expires_in > 0 else 3600.0
        now = time.monotonic()
        self._expires_at = now + life
        self._renew_at = now + life - min(EXPIRY_MARGIN_S, life / 10)
        self.generation += 1
        self.refreshes += 1
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
