"""The Data Link's forwarding, as a plain ASGI app in front of the platform's routes.

Order of checks (the paper's, section IV): no or invalid token -> 401; a token without the
right for this twin and method -> 403 (viewers read: GET, HEAD, OPTIONS; editors also write);
unknown service -> 404; then the service's credentials are added and the request forwarded on
a pooled connection. A 401 from the service makes the gateway renew the credentials once
(one renewal for any number of requests refused together) and send the request again; if the
renewal fails the answer is a problem saying so. Bodies stream both ways.
"""

from __future__ import annotations

import logging

from twinlink.auth.service import AuthService
from twinlink.gateway import paths
from twinlink.gateway.access import bearer, caller_of, resolve
from twinlink.gateway.exchange import (
    ASGIApp,
    Exchange,
    GatewayProblem,
    Receive,
    Scope,
    Send,
    send_problem,
)
from twinlink.gateway.sender import Sender
from twinlink.gateway.service import GatewayService
from twinlink.gateway.signin import renew, sign_in
from twinlink.gateway.table import Service
from twinlink.gateway.wsproxy import forward_websocket

log = logging.getLogger("twinlink.gateway")
# Request bodies up to this size are kept, so the request can be sent again after the
# service's credentials are renewed; larger ones stream straight through.
REPLAY_LIMIT = 1 << 20
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


class GatewayApp:
    """Routes gateway paths to the proxy and everything else to `app`."""

    def __init__(self, app: ASGIApp, gateway: GatewayService, auth: AuthService) -> None:
        self.app = app
        self.gateway = gateway
        self.auth = auth

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        kind = scope["type"]
        route = None
        if kind == "http" or kind == "websocket":
            route = paths.match(scope.get("raw_path") or scope["path"].encode())
        if route is None:
            await self.app(scope, receive, send)
        elif kind == "http":
            await self.http(scope, receive, send, route)
        else:
            await forward_websocket(self.gateway, self.auth, scope, receive, send, route)

    async def http(self, scope: Scope, receive: Receive, send: Send, route: paths.Route) -> None:
        method: str = scope["method"]
        ex = Exchange(method, "/" + route.rest.decode("latin-1"))
        ex.service = route.service
        ex.twin = route.twin or self.gateway.default_twin or ""
        service: Service | None = None
        try:
            principal = await caller_of(self.auth, bearer(scope), scope)
            ex.caller = principal.user.username if principal.user else "-"
            need = "viewer" if method in READ_METHODS else "editor"
            service = await resolve(self.gateway, principal, route, need)
            await self.forward(scope, receive, send, route, service, ex)
        except GatewayProblem as problem:
            ex.status = problem.status
            ex.outcome = problem.outcome
            if not problem.sent:
                await send_problem(send, problem)
        except Exception:
            # A bug: logged with its traceback, answered as a problem (and no traceback).
            extra = {"event": "gateway_error", "service": route.service}
            log.exception("gateway request failed", extra=extra)
            answered = ex.outcome == "forwarded"  # the service's answer had started
            ex.status, ex.outcome = 500, "error"
            if not answered:
                await send_problem(send, GatewayProblem(500, "the gateway failed; see its log"))
        finally:
            self.gateway.audit.record(ex.entry())
            if service is not None:
                _count(service, ex)

    async def forward(
        self,
        scope: Scope,
        receive: Receive,
        send: Send,
        route: paths.Route,
        service: Service,
        ex: Exchange,
    ) -> None:
        method: str = scope["method"]
        if service.blocked or service.origin is None:
            raise GatewayProblem(
                503, f"the service {service.name!r} is not usable: {service.blocked}"
            )
        if method not in service.methods:
            allow = ", ".join(sorted(service.methods))
            raise GatewayProblem(
                405,
                f"the service {service.name!r} allows {allow}",
                headers=[(b"allow", allow.encode())],
            )
        try:
            rest = paths.check_rest(route.rest)
        except paths.PathRefused as err:
            raise GatewayProblem(400, f"refused: {err}") from err
        limit = int(service.settings.limits.max_body_mb * 2**20)
        sender = Sender(self.gateway.pool, scope, receive, route, service, rest, limit, ex)
        if sender.declared is not None and sender.declared > limit:
            raise GatewayProblem(
                413,
                f"the service {service.name!r} takes bodies of at most "
                f"{service.settings.limits.max_body_mb:g} MB",
            )
        body, more = await _read_start(receive, limit)
        ex.bytes_in = sum(map(len, body))
        generation = await sign_in(service)
        conn, status, headers = await sender.send(body, more)
        if status == 401:
            await sender.drain(conn)
            await renew(service, generation)
            if more:
                raise GatewayProblem(
                    503,
                    "the service's credentials were renewed; send the request again",
                    outcome="renewed",
                    headers=[(b"retry-after", b"0")],
                )
            conn, status, headers = await sender.send(body, more)
        await sender.respond(send, conn, status, headers)


async def _read_start(receive: Receive, limit: int) -> tuple[list[bytes], bool]:
    """The request body's pieces if it ends within REPLAY_LIMIT, else its first pieces; and
    whether more follows. Pieces are kept apart: joining a megabyte only to send it costs a
    copy."""
    chunks: list[bytes] = []
    size = 0
    while True:
        message = await receive()
        if message["type"] == "http.disconnect":
            raise GatewayProblem(499, "the client went away", outcome="client_left", sent=True)
        chunk = message.get("body", b"")
        size += len(chunk)
        if size > limit:
            raise GatewayProblem(413, "the request body is over the service's size limit")
        chunks.append(chunk)
        if not message.get("more_body", False):
            return chunks, False
        if size > REPLAY_LIMIT:
            return chunks, True


def _count(service: Service, ex: Exchange) -> None:
    stats = service.stats
    stats.requests[ex.status] = stats.requests.get(ex.status, 0) + 1
    stats.bytes_in += ex.bytes_in
    stats.bytes_out += ex.bytes_out
    if ex.upstream_s is not None:
        stats.observe(ex.upstream_s)
    if ex.outcome not in ("forwarded", "refused"):
        stats.failures[ex.outcome] = stats.failures.get(ex.outcome, 0) + 1
