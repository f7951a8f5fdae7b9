"""/api/v1/connector-kinds and /api/v1/twins/{slug}/connectors (docs/connectors.md)."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Request, Response

from twinlink.api.deps import Caller
from twinlink.api.models.connectors import ConnectorKinds, Connectors, ConnectorView
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.connectors.service import ConnectorService

router = APIRouter(
    prefix="/api/v1",
    tags=["connectors"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
# Changing a connector: admins only (403); a name may be taken; the disk may be full.
CHANGING = problems(403, 409, 507)


async def connector_service(request: Request) -> ConnectorService:
    return request.app.state.services.connectors  # type: ignore[no-any-return]


ConnectorsService = Annotated[ConnectorService, Depends(connector_service)]


@router.get(
    "/connector-kinds",
    summary="The kinds of connector with their configuration's JSON schema",
    response_class=JSONAnswer,
    response_model=ConnectorKinds,
)
async def list_kinds(_: Caller, connectors: ConnectorsService) -> JSONAnswer:
    return JSONAnswer({"kinds": connectors.kinds()})


@router.get(
    "/twins/{slug}/connectors",
    summary="The twin's connectors with settings (no secrets) and status (viewers)",
    response_class=JSONAnswer,
    response_model=Connectors,
    responses=problems(403),
)
async def list_connectors(slug: str, caller: Caller, connectors: ConnectorsService) -> JSONAnswer:
    return JSONAnswer({"connectors": await connectors.list_connectors(caller, slug)})


@router.post(
    "/twins/{slug}/connectors",
    summary="Create a connector (admins); it starts at once unless `enabled` is false, and "
    "nothing is kept when it cannot start",
    response_class=JSONAnswer,
    status_code=201,
    response_model=ConnectorView,
    responses=CHANGING,
)
async def create_connector(
    slug: str,
    caller: Caller,
    connectors: ConnectorsService,
    body: Annotated[
        dict[str, Any],
        Body(description="`name`, `kind`, `config`, optional `device` and `enabled`"),
    ],
) -> JSONAnswer:
    return JSONAnswer(await connectors.create(caller, slug, body), status_code=201)


@router.get(
    "/twins/{slug}/connectors/{name}",
    summary="A connector: settings (no secrets) and status (viewers)",
    response_class=JSONAnswer,
    response_model=ConnectorView,
    responses=problems(403),
)
async def get_connector(
    slug: str, name: str, caller: Caller, connectors: ConnectorsService
) -> JSONAnswer:
    return JSONAnswer(await connectors.get(caller, slug, name))


@router.patch(
    "/twins/{slug}/connectors/{name}",
    summary="Change `config` (fields given; secrets left out are kept) or `enabled` (admins); "
    "it restarts with them, or nothing changes when it cannot start",
    response_class=JSONAnswer,
    response_model=ConnectorView,
    responses=CHANGING,
)
async def update_connector(
    slug: str,
    name: str,
    caller: Caller,
    connectors: ConnectorsService,
    changes: Annotated[dict[str, Any], Body(description="`config` and/or `enabled`")],
) -> JSONAnswer:
    return JSONAnswer(await connectors.update(caller, slug, name, changes))


@router.post(
    "/twins/{slug}/connectors/{name}/start",
    summary="Enable and start (admins)",
    response_class=JSONAnswer,
    response_model=ConnectorView,
    responses=CHANGING,
)
async def start_connector(
    slug: str, name: str, caller: Caller, connectors: ConnectorsService
) -> JSONAnswer:
    return JSONAnswer(await connectors.update(caller, slug, name, {"enabled": True}))


@router.post(
    "/twins/{slug}/connectors/{name}/stop",
    summary="Stop and disable (admins)",
    response_class=JSONAnswer,
    response_model=ConnectorView,
    responses=CHANGING,
)
async def stop_connector(
    slug: str, name: str, caller: Caller, connectors: ConnectorsService
) -> JSONAnswer:
    return JSONAnswer(await connectors.update(caller, slug, name, {"enabled": False}))


@router.post(
    "/twins/{slug}/connectors/{name}/restart",
    summary="Restart (admins)",
    response_class=JSONAnswer,
    response_model=ConnectorView,
    responses=CHANGING,
)
async def restart_connector(
    slug: str, name: str, caller: Caller, connectors: ConnectorsService
) -> JSONAnswer:
    return JSONAnswer(await connectors.restart(caller, slug, name))


@router.delete(
    "/twins/{slug}/connectors/{name}",
    summary="Delete (admins)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_connector(
    slug: str, name: str, caller: Caller, connectors: ConnectorsService
) -> Response:
    await connectors.delete(caller, slug, name)
    return Response(status_code=204)
