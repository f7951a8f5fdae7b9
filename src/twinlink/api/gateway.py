"""/api/v1/twins/{slug}/services (the gateway's service registry), their health, service
accounts, and /api/v1/gateway/audit. The forwarding itself is not here: it is the ASGI app
in `twinlink.gateway.proxy`, in front of these routes."""

from __future__ import annotations

import time
from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Query, Request, Response

from twinlink.api.deps import Caller
from twinlink.api.models.gateway import (
    AuditPage,
    NewServiceAccount,
    ServiceAccountList,
    ServiceDeleted,
    ServiceHealth,
    Services,
    ServiceView,
)
from twinlink.api.models.problem import problems
from twinlink.api.params import HttpStatus, OlderThan, UnixSeconds
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.domain.errors import ForbiddenError, InvalidInputError
from twinlink.gateway import health
from twinlink.gateway.accounts import ServiceAccounts
from twinlink.gateway.service import GatewayService
from twinlink.gateway.table import Service

router = APIRouter(
    prefix="/api/v1",
    tags=["gateway"],
    route_class=ExactJsonRoute,
    responses=problems(401, 403, 404, 422, 503),
)
# Changing services or accounts: a name may be taken; the disk may be full.
CHANGING = problems(409, 507)


async def gateway_service(request: Request) -> GatewayService:
    return request.app.state.services.gateway  # type: ignore[no-any-return]


async def accounts_service(request: Request) -> ServiceAccounts:
    services = request.app.state.services
    return ServiceAccounts(services.auth, services.registry, services.store)


Gateway = Annotated[GatewayService, Depends(gateway_service)]
Accounts = Annotated[ServiceAccounts, Depends(accounts_service)]
Settings = Annotated[dict[str, Any], Body(description="the service's settings")]


def view(service: Service) -> dict[str, Any]:
    stats = service.stats
    return {
        **service.public(),
        "health": stats.health,
        "requests": sum(stats.requests.values()),
        "stats": stats.summary(),
        "credential_refreshes": service.credentials.refreshes,
        "credential_error": service.credentials.last_error,
    }


@router.get(
    "/twins/{slug}/services",
    summary="The twin's gateway services: features with an apiAddress and those added by API "
    "(viewers); credentials show only whether each secret is set",
    response_class=JSONAnswer,
    response_model=Services,
)
async def list_services(slug: str, caller: Caller, gateway: Gateway) -> JSONAnswer:
    return JSONAnswer({"services": [view(s) for s in await gateway.list(caller, slug)]})


@router.post(
    "/twins/{slug}/services",
    summary="Add a service by API (owners): name, base_url, auth, methods, limits, health_path",
    response_class=JSONAnswer,
    status_code=201,
    response_model=ServiceView,
    responses=CHANGING,
)
async def create_service(slug: str, body: Settings, caller: Caller, gateway: Gateway) -> Response:
    settings = dict(body)
    name = settings.pop("name", None)
    if not isinstance(name, str):
        raise InvalidInputError("a service needs a `name`")
    made = await gateway.create(caller, slug, name, settings)
    return JSONAnswer(view(made), status_code=201)


@router.get(
    "/twins/{slug}/services/{name}",
    summary="One service (viewers)",
    response_class=JSONAnswer,
    response_model=ServiceView,
)
async def get_service(slug: str, name: str, caller: Caller, gateway: Gateway) -> JSONAnswer:
    return JSONAnswer(view(await gateway.get(caller, slug, name)))


@router.patch(
    "/twins/{slug}/services/{name}",
    summary="Change a service's settings or credentials (owners). Secret fields left out of an "
    "`auth` of the same method are kept",
    response_class=JSONAnswer,
    response_model=ServiceView,
    responses=CHANGING,
)
async def update_service(
    slug: str, name: str, body: Settings, caller: Caller, gateway: Gateway
) -> JSONAnswer:
    return JSONAnswer(view(await gateway.update(caller, slug, name, body)))


@router.delete(
    "/twins/{slug}/services/{name}",
    summary="Delete a service added by API, or reset a document service's settings (owners)",
    response_class=JSONAnswer,
    response_model=ServiceDeleted,
    responses=CHANGING,
)
async def delete_service(slug: str, name: str, caller: Caller, gateway: Gateway) -> JSONAnswer:
    return JSONAnswer({"service": name, "outcome": await gateway.delete(caller, slug, name)})


@router.get(
    "/twins/{slug}/services/{name}/health",
    summary="Check the service now: a GET of its health_path (or base URL) with its credentials",
    response_class=JSONAnswer,
    response_model=ServiceHealth,
)
async def check_service(slug: str, name: str, caller: Caller, gateway: Gateway) -> JSONAnswer:
    service = await gateway.get(caller, slug, name)
    return JSONAnswer({"service": name, **(await health.check(gateway, service))})


@router.get(
    "/gateway/audit",
    summary="Requests the gateway answered, newest first. Admins see all; others name a "
    "`twin` they own",
    response_class=JSONAnswer,
    response_model=AuditPage,
)
async def audit(
    caller: Caller,
    gateway: Gateway,
    twin: str | None = None,
    service: str | None = None,
    user: Annotated[str | None, Query(description="the caller's username")] = None,
    method: str | None = None,
    status: HttpStatus = None,
    since: UnixSeconds = None,
    until: UnixSeconds = None,
    limit: Annotated[int, Query(ge=1, le=10_000)] = 100,
    before: OlderThan = None,
) -> JSONAnswer:
    if not caller.is_admin:
        if twin is None:
            raise ForbiddenError("the whole audit log is for admins; name a `twin` you own")
        await gateway.require_owner(caller, twin)
    await gateway.audit.flush()
    filters = {
        "twin": twin,
        "service": service,
        "caller": user,
        "method": method.upper() if method else None,
        "status": status,
        "since_ns": None if since is None else round(since * 1e9),
        "until_ns": None if until is None else round(until * 1e9),
    }
    entries = await gateway.store.list_audit(filters, limit, before)
    return JSONAnswer(_audit_page(entries, limit))


def _audit_page(entries: list[Any], limit: int) -> dict[str, Any]:
    return {
        "entries": [
            {
                "id": e.id,
                "time": e.time_ns / 1e9,
                "time_iso": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(e.time_ns / 1e9)),
                "twin": e.twin,
                "service": e.service,
                "caller": e.caller,
                "method": e.method,
                "path": e.path,
                "status": e.status,
                "outcome": e.outcome,
                "bytes_in": e.bytes_in,
                "bytes_out": e.bytes_out,
                "upstream_ms": e.upstream_ms,
                "total_ms": e.total_ms,
            }
            for e in entries
        ],
        "next_before": entries[-1].id if len(entries) == limit else None,
    }


@router.get(
    "/twins/{slug}/service-accounts",
    summary="The twin's service accounts (owners)",
    response_class=JSONAnswer,
    response_model=ServiceAccountList,
)
async def list_accounts(slug: str, caller: Caller, accounts: Accounts) -> JSONAnswer:
    return JSONAnswer({"service_accounts": await accounts.list(caller, slug)})


@router.post(
    "/twins/{slug}/service-accounts",
    summary="Make a service account for a feature that calls other services through the "
    "gateway (owners); its token is shown once",
    response_class=JSONAnswer,
    status_code=201,
    response_model=NewServiceAccount,
    responses=CHANGING,
)
async def create_account(
    slug: str,
    caller: Caller,
    accounts: Accounts,
    body: Annotated[dict[str, Any], Body(description="name and role (viewer or editor)")],
) -> Response:
    made = await accounts.create(caller, slug, str(body.get("name", "")), body.get("role"))
    return JSONAnswer(made, status_code=201)


@router.delete(
    "/twins/{slug}/service-accounts/{name}",
    summary="Delete a service account and its tokens (owners)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_account(slug: str, name: str, caller: Caller, accounts: Accounts) -> Response:
    await accounts.delete(caller, slug, name)
    return Response(status_code=204)
