"""Signing requests in to a service, and getting new credentials when it refuses them.

Static methods (basic, bearer, API key) put the stored values on each request; a 401 from the
service cannot be cured by the gateway, so their refresh fails with a message saying so.
Token methods (OAuth2 client credentials and password grant, custom login) fetch a token,
keep it until shortly before it expires, and fetch a new one when the service answers 401.
Any number of requests refused at once cause one fetch: each says which token it used, and
only the first to ask for a refresh of that token performs it; the others share its outcome,
a failure included (a failing login endpoint is not called once per waiting request).
"""

from __future__ import annotations

import asyncio
import base64
import math
import time
from typing import Any
from urllib.parse import quote, unquote_plus

import httpx

from twinlink.gateway.headers import is_field_value
from twinlink.gateway.spec import (
    ApiKeyAuth,
    AuthSettings,
    BasicAuth,
    BearerAuth,
    CustomLogin,
    OAuth2ClientCredentials,
    OAuth2Password,
)

Headers = list[tuple[bytes, bytes]]
# A token is renewed this long (or 10% of its life, if less) before it expires.
EXPIRY_MARGIN_S = 10.0
LOGIN_TIMEOUT_S = 15.0


class RefreshError(Exception):
    """New credentials could not be obtained; the message never holds a secret."""


class Credentials:
    """Base: no credentials at all."""

    method = "none"
    can_refresh = False

    def __init__(self) -> None:
        self.generation = 0
        self.refreshes = 0
        self.last_error: str | None = None

    async def ready(self) -> int:
        """Credentials usable now; the generation to report if the service refuses them."""
        return self.generation

    def apply(self, headers: Headers, query: list[str]) -> None:
        """Add the credentials to a request's headers or query parameters."""

    def client_query(self, query: bytes) -> bytes:
        """The caller's query string as sent on: without a parameter the credentials set."""
        return query

    async def refresh(self, refused_generation: int) -> None:
        raise RefreshError(
            f"the service refused the gateway's {self.method} credentials, which the gateway "
            "cannot renew by itself; an owner of the twin must set new ones"
        )

    def secrets(self) -> list[str]:
        """Secret values, for scrubbing them out of anything shown."""
        return []


class StaticHeader(Credentials):
    def __init__(self, method: str, name: str, value: str, secret: str) -> None:
        super().__init__()
        self.method = method
        self._header = (name.lower().encode("latin-1"), value.encode("latin-1"))
        self._secret = secret

    def apply(self, headers: Headers, query: list[str]) -> None:
        _replace(headers, self._header)

    def secrets(self) -> list[str]:
        return [self._secret]


class QueryKey(Credentials):
    method = "api_key"

    def __init__(self, name: str, value: str) -> None:
        super().__init__()
        self._name = name
        self._param = f"{quote(name, safe='')}={quote(value, safe='')}"
        self._value = value

    def apply(self, headers: Headers, query: list[str]) -> None:
        query.append(self._param)

    def client_query(self, query: bytes) -> bytes:
        # A key of the caller's own under the same name would leave the service two to pick
        # from; only the gateway's is sent.
        pairs = query.split(b"&") if query else []
        return b"&".join(
            p for p in pairs if unquote_plus(p.partition(b"=")[0].decode("latin-1")) != self._name
        )

    def secrets(self) -> list[str]:
        return [self._value]


class TokenCredentials(Credentials):
    """A token fetched from a login endpoint and renewed on expiry or refusal. Its
    `generation` counts the fetches that finished, whether they got a token or not."""

    can_refresh = True

    def __init__(self, method: str, header: str, template: str) -> None:
        super().__init__()
        self.method = method
        self._header_name = header.lower().encode("latin-1")
        self._template = template
        self._header: tuple[bytes, bytes] | None = None
        self._renew_at = 0.0
        self._expires_at = 0.0
        self._lock = asyncio.Lock()

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
            _replace(headers, self._header)

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
                value = self._template.replace("{token}", token)
                if not is_field_value(value):
                    # A line break would end the header and could smuggle a request onto a
                    # pooled connection; a character outside Latin-1 cannot be sent at all.
                    raise RefreshError("the login endpoint sent a token that cannot go in a header")
            except RefreshError as err:
                self.last_error = str(err)
                self.generation += 1
                raise
            self._header = (self._header_name, value.encode("latin-1"))
            life = expires_in if expires_in and expires_in > 0 else 3600.0
            now = time.monotonic()
            self._expires_at = now + life
            self._renew_at = now + life - min(EXPIRY_MARGIN_S, life / 10)
            self.generation += 1
            self.refreshes += 1
            self.last_error = None

    async def fetch(self) -> tuple[str, float | None]:
        raise NotImplementedError

    async def post(self, url: str, **kwargs: Any) -> httpx.Response:
        try:
            async with httpx.AsyncClient(timeout=LOGIN_TIMEOUT_S, follow_redirects=False) as c:
                return await c.post(url, **kwargs)
        except httpx.HTTPError as err:
            raise RefreshError(
                f"the login endpoint {url} could not be reached: {type(err).__name__}"
            ) from None


class OAuth2(TokenCredentials):
    def __init__(self, auth: OAuth2ClientCredentials | OAuth2Password) -> None:
        super().__init__(auth.method, "authorization", "Bearer {token}")
        self.auth = auth

    async def fetch(self) -> tuple[str, float | None]:
        a = self.auth
        form: dict[str, str] = {"grant_type": "client_credentials"}
        if isinstance(a, OAuth2Password):
            form = {"grant_type": "password", "username": a.username, "password": a.password}
        if a.scope:
            form["scope"] = a.scope
        headers = {"Accept": "application/json"}
        if a.client_id is not None:
            if a.client_auth == "basic":
                pair = f"{quote(a.client_id, safe='')}:{quote(a.client_secret or '', safe='')}"
                headers["Authorization"] = "Basic " + base64.b64encode(pair.encode()).decode()
            else:
                form["client_id"] = a.client_id
                form["client_secret"] = a.client_secret or ""
        answer = await self.post(a.token_url, data=form, headers=headers)
        body = _json(answer)
        if answer.status_code != 200 or not isinstance(body.get("access_token"), str):
            reason = body.get("error_description") or body.get("error") or "no access_token"
            raise RefreshError(
                f"the token endpoint {a.token_url} answered {answer.status_code}: "
                f"{scrub(str(reason)[:200], self.secrets())}"
            )
        return body["access_token"], _seconds(body.get("expires_in"))

    def secrets(self) -> list[str]:
        a = self.auth
        values = [a.client_secret or ""]
        if isinstance(a, OAuth2Password):
            values.append(a.password)
        return [v for v in values if v]


class Login(TokenCredentials):
    def __init__(self, auth: CustomLogin) -> None:
        super().__init__("custom_login", auth.header, auth.template)
        self.auth = auth

    async def fetch(self) -> tuple[str, float | None]:
        a = self.auth
        answer = await self.post(a.login_url, json=a.body, headers={"Accept": "application/json"})
        body = _json(answer)
        token = json_path(body, a.token_path)
        if not 200 <= answer.status_code < 300 or not isinstance(token, str | int) or not token:
            reason = "" if answer.status_code >= 300 else f"; no token at {a.token_path!r}"
            raise RefreshError(f"the login at {a.login_url} answered {answer.status_code}{reason}")
        expires = json_path(body, a.expires_in_path) if a.expires_in_path else None
        return str(token), _seconds(expires)

    def secrets(self) -> list[str]:
        return [str(v) for v in _leaves(self.auth.body) if str(v)]


def credentials_for(auth: AuthSettings) -> Credentials:
    if isinstance(auth, BasicAuth):
        pair = base64.b64encode(f"{auth.username}:{auth.password}".encode()).decode()
        return StaticHeader("basic", "authorization", f"Basic {pair}", auth.password)
    if isinstance(auth, BearerAuth):
        return StaticHeader("bearer", "authorization", f"Bearer {auth.token}", auth.token)
    if isinstance(auth, ApiKeyAuth):
        if auth.in_ == "query":
            return QueryKey(auth.name, auth.value)
        return StaticHeader("api_key", auth.name, auth.value, auth.value)
    if isinstance(auth, OAuth2ClientCredentials | OAuth2Password):
        return OAuth2(auth)
    if isinstance(auth, CustomLogin):
        return Login(auth)
    return Credentials()


def _replace(headers: Headers, header: tuple[bytes, bytes]) -> None:
    """Set `header`, dropping any the caller sent under that name: the service must see the
    gateway's credentials only, not a second value to choose from."""
    headers[:] = [h for h in headers if h[0] != header[0]]
    headers.append(header)


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


def scrub(text: str, secrets: list[str]) -> str:
    for secret in secrets:
        if len(secret) >= 3:
            text = text.replace(secret, "***")
    return text


def _json(answer: httpx.Response) -> dict[str, Any]:
    try:
        body = answer.json()
    except ValueError:
        return {}
    return body if isinstance(body, dict) else {}


def _seconds(value: Any) -> float | None:
    """A login endpoint's `expires_in`, or None (renewed after the default hour) when it is
    not a finite number: `1e400` reads as infinity, a 400-digit integer overflows a float."""
    try:
        seconds = float(value) if value is not None else None
    except (TypeError, ValueError, OverflowError):
        return None
    return seconds if seconds is not None and math.isfinite(seconds) else None


def _leaves(value: Any) -> list[Any]:
    if isinstance(value, dict):
        return [leaf for v in value.values() for leaf in _leaves(v)]
    if isinstance(value, list):
        return [leaf for v in value for leaf in _leaves(v)]
    return [value]
