"""A real upstream service for the gateway tests: an ASGI app served by uvicorn on two loopback
ports (two origins) in a background thread with its own event loop.

The first path segment picks how a request must sign in (its "realm"): `open`, `basic`,
`bearer`, `key-header` (X-Api-Key), `key-query` (`api_key=`), `oauth` (a Bearer token from
`/_auth/token`, both grants) and `login` (`Authorization: Token <t>` from `/_auth/login`,
which answers `{"data": {"token", "expires_in"}}`). Below the realm:

    echo/...        the request as JSON (method, raw path, raw query, headers, body size, sha256)
    bytes/<n>       n bytes made on the fly (`?chunked=1`: without Content-Length)
    sse/<key>       one event, then the last one once the test calls `release(key)`
    slow            no answer until the client gives up
    redirect/<how>  a redirect inside or outside the realm
    cookie, hop     answers with Set-Cookie, with hop-by-hop headers
    ws              (WebSocket) echo; a text `close:<code>:<reason>` closes with that code

(those answers are in `_upstream_answers.py`).

Every request that arrives is logged (`seen`) before any check, so a test can prove that a
refused request never reached the service. Counters of tokens issued and of 401s given are
read by the tests; `revoke_all` makes every issued token invalid at once.
"""

from __future__ import annotations

import asyncio
import base64
import json
import secrets
import socket
import threading
import time
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import parse_qs, unquote_plus

import pytest
import uvicorn

from tests.integration._upstream_answers import (
    ANSWERS,
    WAIT_S,
    Call,
    Seen,
    echo,
    read_body,
    send_json,
    websocket_echo,
)

Scope = dict[str, Any]
REALMS = ("open", "basic", "bearer", "key-header", "key-query", "oauth", "login")


@dataclass(frozen=True)
class Secrets:
    """The credentials the upstream accepts; random per instance, distinctive to grep for."""

    basic_user: str = field(default_factory=lambda: "user-" + secrets.token_hex(4))
    basic_password: str = field(default_factory=lambda: "SECRET-basic-" + secrets.token_hex(8))
    bearer: str = field(default_factory=lambda: "SECRET-bearer-" + secrets.token_hex(8))
    api_key: str = field(default_factory=lambda: "SECRET-key-" + secrets.token_hex(8))
    client_id: str = field(default_factory=lambda: "client-" + secrets.token_hex(4))
    # Characters that must be form-encoded in HTTP Basic client authentication (RFC 6749).
    client_secret: str = field(default_factory=lambda: "SECRET-client:+/" + secrets.token_hex(8))
    oauth_user: str = field(default_factory=lambda: "owner-" + secrets.token_hex(4))
    oauth_password: str = field(default_factory=lambda: "SECRET-grant-" + secrets.token_hex(8))
    login_user: str = field(default_factory=lambda: "login-" + secrets.token_hex(4))
    login_password: str = field(default_factory=lambda: "SECRET-login-" + secrets.token_hex(8))

    def values(self) -> list[str]:
        return [v for k, v in vars(self).items() if "user" not in k and k != "client_id"]


class Upstream:
    def __init__(self) -> None:
        self.secrets = Secrets()
        self.seen: list[Seen] = []
        self.issued: Counter[str] = Counter()  # tokens issued by endpoint: oauth, login
        self.attempts: Counter[str] = Counter()  # calls of each token endpoint, failed or not
        self.refused: Counter[str] = Counter()  # 401s given, by realm
        self.all_tokens: list[str] = []  # every token issued, to look for in logs
        self.grants: list[tuple[str, str]] = []  # (grant_type, client auth: basic|body|none)
        self.ws_closes: list[int] = []  # close codes the upstream received from clients
        self.errors: list[str] = []
        self.expires_in = 3600.0  # the expires_in of new tokens
        self.token_endpoints_down = False
        self.next_token: str | None = None  # the value of the next token issued, if not random
        self._tokens: dict[str, set[str]] = {"oauth": set(), "login": set()}
        self._hold = 0  # refusals to gather before answering any of them (0: answer at once)
        self._holding: list[asyncio.Event] = []
        self._releases: dict[str, asyncio.Event] = {}
        self._lock = threading.Lock()
        self._sockets = [_listen(), _listen()]
        self.port, self.other_port = (s.getsockname()[1] for s in self._sockets)
        self.url = f"http://127.0.0.1:{self.port}"
        self.other_url = f"http://127.0.0.1:{self.other_port}"
        self._loop: asyncio.AbstractEventLoop | None = None
        config = uvicorn.Config(
            self, lifespan="off", log_config=None, access_log=False, ws="websockets-sansio",
            timeout_graceful_shutdown=5, ws_max_size=64 << 20,
        )  # fmt: skip
        self._server = uvicorn.Server(config)
        self._thread = threading.Thread(target=self._run, name="upstream", daemon=True)

    # -- what tests call ---------------------------------------------------------------------

    def start(self) -> Upstream:
        self._thread.start()
        deadline = time.monotonic() + 20
        while not self._server.started:
            if not self._thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError("the test upstream did not start")
            time.sleep(0.01)
        return self

    def stop(self) -> None:
        self._server.should_exit = True
        self._thread.join(timeout=20)
        for sock in self._sockets:
            sock.close()

    def base(self, realm: str, other: bool = False) -> str:
        return f"{self.other_url if other else self.url}/{realm}/"

    def requests_to(self, marker: str) -> list[Seen]:
        with self._lock:
            return [s for s in self.seen if marker in s.raw_path or marker in s.query]

    def revoke_all(self) -> None:
        """Every token issued so far is refused from now on."""
        with self._lock:
            for tokens in self._tokens.values():
                tokens.clear()

    def hold_refusals(self, count: int) -> None:
        """Answer the next `count` refused requests only once all of them have arrived."""
        with self._lock:
            self._hold = count

    def release(self, key: str) -> None:
        """Let the SSE stream `key` send its last event."""
        assert self._loop is not None
        self._loop.call_soon_threadsafe(
            lambda: self._releases.setdefault(key, asyncio.Event()).set()
        )

    # -- the server thread -------------------------------------------------------------------

    def _run(self) -> None:
        self._server.run(sockets=self._sockets)

    async def __call__(self, scope: Scope, receive: Any, send: Any) -> None:
        self._loop = asyncio.get_running_loop()
        raw_path = (scope.get("raw_path") or scope["path"].encode()).decode("latin-1")
        query = scope["query_string"].decode("latin-1")
        headers = [(k.decode("latin-1"), v.decode("latin-1")) for k, v in scope["headers"]]
        kind = scope["type"]
        seen = Seen(kind, scope.get("method", "WEBSOCKET"), raw_path, query, headers)
        with self._lock:
            self.seen.append(seen)
        try:
            if kind == "websocket":
                await self._websocket(scope, receive, send, seen)
            else:
                await self._http(scope, receive, send, seen)
        except Exception as err:
            self.errors.append(f"{type(err).__name__}: {err}")
            raise

    async def _websocket(self, scope: Scope, receive: Any, send: Any, seen: Seen) -> None:
        await receive()  # websocket.connect
        realm = scope["path"].lstrip("/").partition("/")[0]
        if realm not in REALMS or not self._authorized(realm, seen):
            with self._lock:
                self.refused[realm] += 1
            await send({"type": "websocket.http.response.start", "status": 401, "headers": []})
            await send({"type": "websocket.http.response.body", "body": b"unauthorized"})
            return
        await websocket_echo(
            Call(scope, receive, send, seen, realm, "", self._releases, self.ws_closes)
        )

    async def _http(self, scope: Scope, receive: Any, send: Any, seen: Seen) -> None:
        path: str = scope["path"]
        if path == "/_auth/token":
            await self._token(receive, send, seen)
            return
        if path == "/_auth/login":
            await self._login(receive, send)
            return
        realm, _, rest = path.lstrip("/").partition("/")
        if realm not in REALMS:
            await send_json(send, 404, {"error": f"no realm {realm!r}"})
            return
        if not self._authorized(realm, seen):
            await self._refuse(realm, send)
            return
        what, _, arg = rest.partition("/")
        call = Call(scope, receive, send, seen, realm, arg, self._releases, self.ws_closes)
        await ANSWERS.get(what, echo)(call)

    # -- credentials -------------------------------------------------------------------------

    def _authorized(self, realm: str, seen: Seen) -> bool:
        s = self.secrets
        auth = seen.header("authorization")
        if realm == "open":
            return True
        if realm == "basic":
            pair = base64.b64encode(f"{s.basic_user}:{s.basic_password}".encode()).decode()
            return auth == [f"Basic {pair}"]
        if realm == "bearer":
            return auth == [f"Bearer {s.bearer}"]
        if realm == "key-header":
            return seen.header("x-api-key") == [s.api_key]
        if realm == "key-query":
            return parse_qs(seen.query).get("api_key") == [s.api_key]
        scheme = "Bearer " if realm == "oauth" else "Token "
        with self._lock:
            valid = {scheme + t for t in self._tokens[realm]}
        return len(auth) == 1 and auth[0] in valid

    async def _refuse(self, realm: str, send: Any) -> None:
        with self._lock:
            self.refused[realm] += 1
            hold = self._hold
        if hold:
            gate = asyncio.Event()
            self._holding.append(gate)
            if len(self._holding) >= hold:
                with self._lock:
                    self._hold = 0
                for waiting in self._holding:
                    waiting.set()
                self._holding.clear()
            await asyncio.wait_for(gate.wait(), WAIT_S)
        await send_json(send, 401, {"error": "unauthorized"}, [(b"www-authenticate", b"Bearer")])

    def _issue(self, endpoint: str) -> str:
        with self._lock:
            token, self.next_token = self.next_token or secrets.token_urlsafe(16), None
            self._tokens[endpoint].add(token)
            self.all_tokens.append(token)
            self.issued[endpoint] += 1
        return token

    async def _token(self, receive: Any, send: Any, seen: Seen) -> None:
        s = self.secrets
        form = {k: v[0] for k, v in parse_qs((await read_body(receive)).decode()).items()}
        client, mode = (form.get("client_id"), form.get("client_secret")), "body"
        basic = seen.header("authorization")
        if basic and basic[0].startswith("Basic "):
            user, _, password = base64.b64decode(basic[0][6:]).decode().partition(":")
            client, mode = (unquote_plus(user), unquote_plus(password)), "basic"
        elif client == (None, None):
            mode = "none"
        grant = form.get("grant_type", "")
        self.grants.append((grant, mode))
        self.attempts["oauth"] += 1
        if self.token_endpoints_down:
            await send_json(send, 503, {"error": "temporarily_unavailable"})
            return
        client_ok = client == (s.client_id, s.client_secret)
        if grant == "password":
            ok = (form.get("username"), form.get("password")) == (s.oauth_user, s.oauth_password)
            ok = ok and (mode == "none" or client_ok)
        else:
            ok = grant == "client_credentials" and client_ok
        if not ok:
            # A careless service that echoes what it was sent: the gateway must scrub it.
            said = f"invalid credentials: {client[1]} {form.get('password')}"
            await send_json(send, 401, {"error": "invalid_client", "error_description": said})
            return
        token = self._issue("oauth")
        answer = {"access_token": token, "token_type": "Bearer", "expires_in": self.expires_in}
        await send_json(send, 200, answer)

    async def _login(self, receive: Any, send: Any) -> None:
        s = self.secrets
        body = json.loads(await read_body(receive) or b"{}")
        self.attempts["login"] += 1
        if self.token_endpoints_down:
            await send_json(send, 503, {"error": "down"})
        elif (body.get("user"), body.get("password")) != (s.login_user, s.login_password):
            await send_json(send, 401, {"error": f"bad password {body.get('password')}"})
        else:
            token = self._issue("login")
            await send_json(send, 200, {"data": {"token": token, "expires_in": self.expires_in}})


def _listen() -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.bind(("127.0.0.1", 0))
    sock.listen(512)
    return sock


@pytest.fixture(scope="module")
def upstream() -> Iterator[Upstream]:
    """A running test upstream, shared by the tests of one module."""
    server = Upstream().start()
    try:
        yield server
    finally:
        server.stop()
    assert not server.errors, server.errors
