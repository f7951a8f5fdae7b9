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

from twinlink.auth.rights import Principal, has_role
from twinlink.auth.service import AuthError, AuthService
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.gateway import paths
from twinlink.gateway.exchange import (
    ASGIApp,
    Exchange,
    GatewayProblem,
    Receive,
    Scope,
    Send,
    send_problem,
)
from twinlink.gateway.headers import content_length
from twinlink.gateway.sender import Sender
from twinlink.gateway.service import GatewayService
from twinlink.gateway.services import Service
from twinlink.gateway.signin import renew, sign_in

log = logging.getLogger("twinlink.gateway")
# Request bodies up to this size are kept, so the request can be sent again after the
# service's credentials are renewed; larger ones stream straight through.
REPLAY_LIMIT = 1 << 20
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


async def caller_of(auth: AuthService, token: str | None) -> Principal:
    if not token:
        raise GatewayProblem(401, "a token is required: send 'Authorization: Bearer <token>'")
    try:
        return await auth.authenticate(token)
    except AuthError as err:
        raise GatewayProblem(
            401, f"{err}. Send a valid token as 'Authorization: Bearer <token>'."
        ) from None


def bearer(scope: Scope) -> str | None:
    for name, value in scope["headers"]:
        if name == b"authorization":
            scheme, _, token = value.decode("latin-1").partition(" ")
            return token.strip() if scheme.lower() == "bearer" else None
    return None


async def resolve(
    gateway: GatewayService, principal: Principal, route: paths.Route, need: str
) -> Service:
    """401 and 403 and 404, in that order, for the service a route names."""
    slug = route.twin or gateway.default_twin
    if slug is None:
        raise GatewayProblem(
            404, "no default twin is set (TWINLINK_GATEWAY_DEFAULT_TWIN); use /twins/{twin}/..."
        )
    try:
        twin, role = await gateway.twin_and_role(principal, slug)
    except ForbiddenError as err:
        raise GatewayProblem(403, str(err)) from None
    except NotFoundError as err:
        raise GatewayProblem(404, str(err)) from None
    if not has_role(principal, role, need):
        what = "reading through" if need == "viewer" else "changing anything through"
        raise GatewayProblem(403, f"{what} the services of {slug!r} needs the {need} role")
    service = (await gateway.services_of(twin)).get(route.service)
    if service is None:
        raise GatewayProblem(404, f"the twin {slug!r} has no service {route.service!r}")
    return service


class GatewayApp:
    """Routes gateway paths to the proxy and everything else to `app`."""

    def __init__(self, app: ASGIApp, gateway: GatewayService, auth: AuthService) -> None:
        self.app = app
        self.gateway = gateway
        self.auth = auth

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            route = paths.match(scope.get("raw_path") or scope["path"].encode())
            if route is not None:
                await self.http(scope, receive, send, route)
                return
        elif scope["type"] == "websocket":
            route = paths.match(scope.get("raw_path") or scope["path"].encode())
            if route is not None:
                from twinlink.gateway.wsproxy import forward_websocket

                await forward_websocket(self, scope, receive, send, route)
                return
        await self.app(scope, receive, send)

    async def http(self, scope: Scope, receive: Receive, send: Send, route: paths.Route) -> None:
        method: str = scope["method"]
        ex = Exchange(method, "/" + route.rest.decode("latin-1"))
        ex.service = route.service
        ex.twin = route.twin or self.gateway.default_twin or ""
        service: Service | None = None
        try:
            principal = await caller_of(self.auth, bearer(scope))
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
            raise GatewayProblem(400, f"refused: {err}") from None
        limit = int(service.settings.limits.max_body_mb * 2**20)
        declared = content_length(scope["headers"])
        if declared is not None and declared > limit:
            raise GatewayProblem(
                413,
                f"the service {service.name!r} takes bodies of at most "
                f"{service.settings.limits.max_body_mb:g} MB",
            )
        body, more = await _read_start(receive, limit)
        ex.bytes_in = sum(map(len, body))
        generation = await sign_in(service)
        sender = Sender(self.gateway.pool, scope, receive, route, service, rest, limit, ex)
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
