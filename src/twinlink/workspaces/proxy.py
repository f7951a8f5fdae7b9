"""`/workspaces/{user}/...`: the proxy to each user's JupyterLab, as a plain ASGI app in
front of FastAPI (as the gateway's), HTTP streamed both ways and WebSockets (wsproxy.py).

Only the workspace's owner passes: with the cookie of a session made from a one-time ticket
(access.py), or with a platform token of theirs (`Authorization: Bearer`, for scripts).
Anyone else is refused 403 before anything reaches JupyterLab, which is never told who
calls: the proxy sends its token on every request. So JupyterLab's own XSRF and origin checks
are skipped (a token-authenticated request needs neither); the proxy makes them unneeded: the
cookie is SameSite=Strict (no other site's page sends it), and a cookie-authenticated request
that changes something, or opens a WebSocket, must come from this server's own origin.
"""

from __future__ import annotations

import contextlib
import logging
import time
from urllib.parse import urlsplit

import httpx

from twinlink.auth.service import AuthError, AuthService
from twinlink.domain.errors import ForbiddenError, NotFoundError, TwinlinkError, UnavailableError
from twinlink.workspaces import _asgi
from twinlink.workspaces._asgi import ASGIApp, Receive, Scope, Send
from twinlink.workspaces.access import COOKIE
from twinlink.workspaces.service import Workspace, WorkspaceService
from twinlink.workspaces.wsproxy import forward_websocket

log = logging.getLogger("twinlink.workspaces")
PREFIX = b"/workspaces/"
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
# Not passed on either way: hop-by-hop headers, and what the proxy decides itself.
_DROPPED = frozenset(
    {
        "connection", "keep-alive", "proxy-authenticate", "proxy-authorization", "te",
        "trailer", "transfer-encoding", "upgrade", "host", "authorization", "cookie", "origin",
    }
)  # fmt: skip
_START = "open it from the app, or start it again: POST /api/v1/workspaces/me gives a new link"


class WorkspaceProxy:
    """Routes /workspaces/{user}/... to that user's JupyterLab, everything else to `app`."""

    def __init__(self, app: ASGIApp, workspaces: WorkspaceService, auth: AuthService) -> None:
        self.app = app
        self.workspaces = workspaces
        self.auth = auth

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        kind = scope["type"]
        path: bytes = b""
        if kind in ("http", "websocket"):
            path = scope.get("raw_path") or scope["path"].encode()
        if not path.startswith(PREFIX) or not self.workspaces.settings.enabled:
            await self.app(scope, receive, send)
            return
        username = path[len(PREFIX) :].split(b"/", 1)[0].decode("latin-1")
        if kind == "websocket":
            await forward_websocket(self.admit, scope, receive, send, username)
        elif path == PREFIX + username.encode("latin-1"):  # the folder without its slash
            location = (
                path + b"/" + (b"?" + scope["query_string"] if scope["query_string"] else b"")
            )
            await _redirect(send, location.decode("latin-1"), [])
        else:
            await self.http(scope, receive, send, username)

    async def admit(self, scope: Scope, username: str, changes: bool) -> Workspace:
        """The running workspace of `username` if the caller is that user; else the error
        to answer (401 for a bad token, 403 for anyone else, 404 when it does not run)."""
        token = _asgi.bearer(scope)
        if token:
            principal = await self.auth.authenticate(token)
            if principal.user is None or principal.user.username != username:
                raise ForbiddenError("a workspace is reached by its owner alone")
        else:
            session = dict(_asgi.cookies(scope)).get(COOKIE)
            if session is None:
                raise ForbiddenError(f"this needs the workspace's session: {_START}")
            if await self.workspaces.access.session(session, username) is None:
                raise ForbiddenError(f"the workspace session is not valid here: {_START}")
            if changes and not _same_origin(scope, self.workspaces.settings.server_url):
                raise ForbiddenError("a change to a workspace must come from this server's pages")
        ws = self.workspaces.running(username)
        if ws is None or ws.process is None:
            raise NotFoundError(f"the workspace of {username} is not running; {_START}")
        ws.touch()
        return ws

    async def http(self, scope: Scope, receive: Receive, send: Send, username: str) -> None:
        ticket, query = _asgi.split_query(scope["query_string"], "ticket")
        try:
            if ticket is not None and scope["method"] == "GET":
                await self.redeem(scope, send, username, ticket, query)
                return
            ws = await self.admit(scope, username, scope["method"] not in SAFE_METHODS)
        except (AuthError, ForbiddenError, NotFoundError) as err:
            await _asgi.send_problem(send, err)
            return
        await self.forward(scope, receive, send, ws)

    async def redeem(
        self, scope: Scope, send: Send, username: str, ticket: str, query: str
    ) -> None:
        """Swap a ticket for the session cookie, and go to the page asked for without it
        (the ticket, used up, stays out of the browser's history)."""
        redeemed = self.workspaces.access.redeem(ticket, username)
        if redeemed is None:
            raise ForbiddenError(f"the link is used up, expired or someone else's: {_START}")
        session, grant = redeemed
        scope_path = f"/workspaces/{username}/"
        cookie = f"{COOKIE}={session}; Path={scope_path}; HttpOnly; SameSite=Strict"
        # TLS here, or ended by a reverse proxy in front (TWINLINK_PUBLIC_URL is https)
        tls = scope.get("scheme") == "https" or self.workspaces.settings.server_url[:6] == "https:"
        if tls:
            cookie += "; Secure"
        if grant.expires_ns is not None:  # it ends with the login session it came from
            cookie += f"; Max-Age={max(0, (grant.expires_ns - time.time_ns()) // 10**9)}"
        path = (scope.get("raw_path") or scope["path"].encode()).decode("latin-1")
        await _redirect(send, path + (f"?{query}" if query else ""), [("set-cookie", cookie)])

    async def forward(self, scope: Scope, receive: Receive, send: Send, ws: Workspace) -> None:
        assert ws.process is not None
        client = self.workspaces.http
        path = (scope.get("raw_path") or scope["path"].encode()).decode("latin-1")
        query = scope["query_string"].decode("latin-1")
        url = ws.process.origin + path + (f"?{query}" if query else "")
        headers = _request_headers(scope, ws.process.token)
        # A body announced by its length or as chunks (the chunked framing itself is
        # hop-by-hop: httpx frames the stream again).
        has_body = any(k in (b"content-length", b"transfer-encoding") for k, _ in scope["headers"])
        content = _body(receive) if has_body else b""
        request = client.build_request(scope["method"], url, headers=headers,
                                                 content=content)  # fmt: skip
        try:
            response = await client.send(request, stream=True)
        except httpx.HTTPError as err:
            await _asgi.send_problem(send, _unreachable(ws, err))
            return
        try:
            await _respond(send, response, ws)
        except httpx.HTTPError as err:  # the answer had started: all that can be done is end
            log.info("workspace answer cut: %s", err, extra={"event": "workspace_cut"})
        finally:
            await response.aclose()


def _unreachable(ws: Workspace, err: Exception) -> TwinlinkError:
    return UnavailableError(
        f"the workspace of {ws.user.username} did not answer ({type(err).__name__}); "
        "if it keeps failing, stop it and start it again"
    )


def _request_headers(scope: Scope, token: str) -> list[tuple[str, str]]:
    headers = [
        (k.decode("latin-1"), v.decode("latin-1"))
        for k, v in scope["headers"]
        if k.decode("latin-1") not in _DROPPED
    ]
    headers.append(("authorization", f"token {token}"))
    kept = _asgi.cookie_header_without(scope, COOKIE)
    if kept:
        headers.append(("cookie", kept))
    return headers


async def _body(receive: Receive):  # type: ignore[no-untyped-def]
    while True:
        message = await receive()
        if message["type"] == "http.disconnect":
            return
        chunk = message.get("body", b"")
        if chunk:
            yield chunk
        if not message.get("more_body", False):
            return


async def _respond(send: Send, response: httpx.Response, ws: Workspace) -> None:
    headers = [
        (k.lower(), v) for k, v in response.headers.raw if k.lower().decode() not in _DROPPED
    ]
    await send({"type": "http.response.start", "status": response.status_code,
                "headers": headers})  # fmt: skip
    async for chunk in response.aiter_raw():
        ws.touch()
        await send({"type": "http.response.body", "body": chunk, "more_body": True})
    await send({"type": "http.response.body", "body": b""})


async def _redirect(send: Send, location: str, extra: list[tuple[str, str]]) -> None:
    headers = [(b"location", location.encode("latin-1")), (b"content-length", b"0"),
               (b"cache-control", b"no-store")]  # fmt: skip
    headers += [(k.encode(), v.encode("latin-1")) for k, v in extra]
    await send({"type": "http.response.start", "status": 303, "headers": headers})
    await send({"type": "http.response.body", "body": b""})


def _same_origin(scope: Scope, server_url: str) -> bool:
    """Whether a browser's request comes from a page of this server: its Origin (sent with
    every cross-origin request, with same-origin ones that change something, and with every
    WebSocket) names the host it was sent to, or the server's public URL (a reverse proxy in
    front may send another Host). A client that sends no Origin is no browser page."""
    origin = _asgi.header(scope, b"origin")
    if origin is None:
        return True
    with contextlib.suppress(ValueError):
        netloc = urlsplit(origin).netloc
        return bool(netloc) and netloc in (
            _asgi.header(scope, b"host"),
            urlsplit(server_url).netloc,
        )
    return False
