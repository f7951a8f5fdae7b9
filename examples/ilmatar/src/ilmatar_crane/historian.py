"""The historian: a MindSphere-type store of the crane's time series with a REST API.

It samples the plant itself (every `period_s`, into a ring buffer of `retention_s`) and hands out
short-lived tokens through its own login call, the kind of "custom method for updating access
tokens" the Data Link paper's gateway had to support: `POST /api/login` with a JSON username and
password answers `{"data": {"token": ..., "expires_in": ...}}`, and calls then send
`Authorization: Token <token>` (not Bearer).
"""

from __future__ import annotations

import asyncio
import re
import secrets
import time
from bisect import bisect_left, bisect_right
from collections import deque
from collections.abc import Awaitable, Callable, Mapping
from datetime import UTC, datetime
from itertools import islice

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ilmatar_crane._http import health, json_body, json_error, page_routes
from ilmatar_crane._tokens import IssuesTokens, TokenStore
from ilmatar_crane.plant import CranePlant
from ilmatar_crane.signals import BY_NAME, SIGNALS

DEFAULT_WINDOW_S = 600.0  # a query without `from` covers the last ten minutes
DEFAULT_LIMIT = 1000
MAX_LIMIT = 10_000
ENDPOINTS = (
    ("POST /api/login", 'Sign in: {"username": ..., "password": ...}; answers a token.'),
    ("GET /api/signals", "The recorded signals with their units."),
    ("GET /api/timeseries?signal=&from=&to=&limit=", "Samples of one signal, oldest first."),
    ("GET /health", "Liveness (no token needed)."),
)
_OFFSET_WITHOUT_PLUS = re.compile(r" (\d{2}:?\d{2})$")
Handler = Callable[[Request], Awaitable[Response]]


class BadQuery(ValueError):
    pass


def parse_time(text: str) -> float:
    """Epoch seconds from epoch seconds or an ISO 8601 time (UTC unless it has an offset)."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        pass
    # An unencoded "+02:00" in a query string arrives as " 02:00".
    text = _OFFSET_WITHOUT_PLUS.sub(r"+\1", text)
    try:
        moment = datetime.fromisoformat(text)
    except ValueError:
        raise BadQuery(f"{text!r} is neither epoch seconds nor an ISO 8601 time") from None
    if moment.tzinfo is None:
        moment = moment.replace(tzinfo=UTC)
    return moment.timestamp()


def iso(epoch: float) -> str:
    return (
        datetime.fromtimestamp(epoch, UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")
    )


class Historian(IssuesTokens):
    def __init__(
        self,
        plant: CranePlant,
        *,
        users: Mapping[str, str],
        token_ttl_s: float = 300.0,
        period_s: float = 1.0,
        retention_s: float = 3 * 3600.0,
        clock: Callable[[], float] = time.time,
    ) -> None:
        self._plant = plant
        self._users = dict(users)
        self._tokens = TokenStore(token_ttl_s)
        self.period_s = period_s
        self._clock = clock
        size = max(1, int(retention_s / period_s))
        self._times: deque[float] = deque(maxlen=size)
        self._values: deque[dict[str, float]] = deque(maxlen=size)
        routes = [
            Route("/health", health),
            Route("/api/login", self._login, methods=["POST"]),
            Route("/api/signals", self._guard(self._signals)),
            Route("/api/timeseries", self._guard(self._timeseries)),
            *page_routes("Ilmatar historian", "The crane's recorded time series.", ENDPOINTS),
        ]
        self.app = Starlette(routes=routes)

    @property
    def logins(self) -> int:
        """Tokens issued so far (each successful login issues one)."""
        return self.tokens_issued

    def sample(self) -> None:
        # Millisecond times, as served: a time read from an answer finds its sample exactly.
        self._times.append(round(self._clock(), 3))
        self._values.append(self._plant.snapshot())

    async def run(self) -> None:
        """Sample for ever, on a fixed grid so the samples do not drift apart."""
        loop = asyncio.get_running_loop()
        start = loop.time()
        ticks = 0
        while True:
            self.sample()
            ticks += 1
            await asyncio.sleep(max(0.0, start + ticks * self.period_s - loop.time()))

    async def _login(self, request: Request) -> Response:
        body = await json_body(request)
        if isinstance(body, Response):
            return body
        username, password = body.get("username"), body.get("password")
        if not isinstance(username, str) or not isinstance(password, str):
            return json_error(422, "invalid_body", 'Send {"username": ..., "password": ...}.')
        expected = self._users.get(username)
        if expected is None or not secrets.compare_digest(password.encode(), expected.encode()):
            return json_error(401, "invalid_credentials", "Unknown user or wrong password.")
        token = self._tokens.issue(username)
        ttl = self._tokens.ttl_s
        return JSONResponse({"data": {"token": token, "token_type": "Token", "expires_in": ttl}})

    def _guard(self, handler: Handler) -> Handler:
        async def guarded(request: Request) -> Response:
            scheme, _, token = request.headers.get("Authorization", "").partition(" ")
            if scheme.lower() != "token" or self._tokens.subject(token.strip()) is None:
                detail = (
                    "Sign in at POST /api/login and send Authorization: Token <token>."
                    if scheme.lower() != "token"
                    else "The token is unknown or has expired; sign in again."
                )
                headers = {"WWW-Authenticate": 'Token realm="historian"'}
                return json_error(401, "unauthorized", detail, headers)
            return await handler(request)

        return guarded

    async def _signals(self, request: Request) -> Response:
        data = [{"name": s.name, "unit": s.unit, "description": s.description} for s in SIGNALS]
        return JSONResponse({"data": data})

    async def _timeseries(self, request: Request) -> Response:
        params = request.query_params
        name = params.get("signal", "")
        signal = BY_NAME.get(name)
        if signal is None:
            known = ", ".join(BY_NAME)
            return json_error(404, "unknown_signal", f"No signal {name!r}; known: {known}.")
        try:
            end = parse_time(params["to"]) if "to" in params else self._clock()
            start = parse_time(params["from"]) if "from" in params else end - DEFAULT_WINDOW_S
            limit = _limit(params.get("limit"))
        except BadQuery as err:
            return json_error(422, "invalid_query", str(err))
        if start > end:
            return json_error(422, "invalid_query", "`from` must not be later than `to`.")
        first = bisect_left(self._times, start)
        stop = bisect_right(self._times, end)
        rows = islice(zip(self._times, self._values, strict=True), first, min(stop, first + limit))
        points = [{"time": iso(t), "value": values[name]} for t, values in rows]
        truncated = stop - first > limit
        return JSONResponse(
            {
                "data": {
                    "signal": name,
                    "unit": signal.unit,
                    "from": iso(start),
                    "to": iso(end),
                    "points": points,
                    "truncated": truncated,
                    # Ask again from here for the rest.
                    "next_from": iso(self._times[first + limit]) if truncated else None,
                }
            }
        )


def _limit(text: str | None) -> int:
    if text is None:
        return DEFAULT_LIMIT
    try:
        limit = int(text)
    except ValueError:
        raise BadQuery(f"limit must be a whole number, got {text!r}") from None
    if not 1 <= limit <= MAX_LIMIT:
        raise BadQuery(f"limit must be between 1 and {MAX_LIMIT}, got {limit}")
    return limit
