"""Who is calling and which service they may reach: the checks every gateway request and
WebSocket goes through first, in the paper's order (401, 403, 404), except that a twin the
caller may not see is 404 before anything else, as everywhere in the API."""

from __future__ import annotations

from twinlink.auth.rights import Principal, has_role
from twinlink.auth.service import AuthError, AuthService, ScopeError
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.gateway import paths
from twinlink.gateway.exchange import GatewayProblem, Scope
from twinlink.gateway.service import GatewayService
from twinlink.gateway.table import Service


async def caller_of(auth: AuthService, token: str | None, scope: Scope) -> Principal:
    if not token:
        raise GatewayProblem(401, "a token is required: send 'Authorization: Bearer <token>'")
    try:  # a scoped token (a run's) is checked against the path here (auth/scopes.py)
        return await auth.authenticate(token, (scope.get("method", "GET"), scope["path"]))
    except ScopeError as err:
        raise GatewayProblem(403, str(err)) from err
    except AuthError as err:
        raise GatewayProblem(
            401, f"{err}. Send a valid token as 'Authorization: Bearer <token>'."
        ) from err


def bearer(scope: Scope) -> str | None:
    for name, value in scope["headers"]:
        if name == b"authorization":
            scheme, _, token = value.decode("latin-1").partition(" ")
            return token.strip() if scheme.lower() == "bearer" else None
    return None


async def resolve(
    gateway: GatewayService, principal: Principal, route: paths.Route, need: str
) -> Service:
    """401, then 404 for a twin the caller may not see (as for an unknown one), 403 for a
    missing role, 404 for an unknown service, in that order, for the service a route names."""
    slug = route.twin or gateway.default_twin
    if slug is None:
        raise GatewayProblem(
            404, "no default twin is set (TWINLINK_GATEWAY_DEFAULT_TWIN); use /twins/{twin}/..."
        )
    try:
        twin, role = await gateway.twin_and_role(principal, slug)
    except ForbiddenError as err:
        raise GatewayProblem(403, str(err)) from err
    except NotFoundError as err:
        raise GatewayProblem(404, str(err)) from err
    if not has_role(principal, role, need):
        what = "reading through" if need == "viewer" else "changing anything through"
        raise GatewayProblem(403, f"{what} the services of {slug!r} needs the {need} role")
    service = (await gateway.services_of(twin)).get(route.service)
    if service is None:
        raise GatewayProblem(404, f"the twin {slug!r} has no service {route.service!r}")
    return service
