"""/api/v1/workspaces: each user's JupyterLab (docs/workspaces.md). The workspace itself is
reached at /workspaces/{user}/ through the proxy (workspaces/proxy.py), not here."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Request, Response

from twinlink.api.deps import Admin, Caller
from twinlink.api.models.problem import problems
from twinlink.api.models.workspaces import Workspaces, WorkspaceView
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.auth.rights import Principal
from twinlink.workspaces.service import Workspace, WorkspaceService

router = APIRouter(
    prefix="/api/v1/workspaces",
    tags=["workspaces"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404),
)


async def workspace_service(request: Request) -> WorkspaceService:
    service: WorkspaceService = request.app.state.services.workspaces
    service.require_enabled()
    return service


Service = Annotated[WorkspaceService, Depends(workspace_service)]


async def _view(service: WorkspaceService, ws: Workspace | None, caller: Principal) -> Any:
    assert caller.user is not None
    if ws is None:
        return {"user": caller.user.username, "state": "stopped", "url": None, "log": []}
    view: dict[str, Any] = {**ws.view(), "url": None}
    if ws.state == "running" and ws.user.username == caller.user.username:
        ticket = await service.access.ticket(caller)
        view["url"] = f"/workspaces/{ws.user.username}/?ticket={ticket}"
    return view


@router.post(
    "/me",
    summary="Start the caller's workspace (a no-op when it runs); answers once it answers, "
    "with a one-time link to it",
    response_class=JSONAnswer,
    response_model=WorkspaceView,
    responses=problems(409, 503),
)
async def start(caller: Caller, service: Service) -> JSONAnswer:
    ws = await service.start(caller)
    return JSONAnswer(await _view(service, ws, caller))


@router.get(
    "/me",
    summary="The caller's workspace: its state, a one-time link while it runs, the last log "
    "lines when it failed",
    response_class=JSONAnswer,
    response_model=WorkspaceView,
)
async def show(caller: Caller, service: Service) -> JSONAnswer:
    assert caller.user is not None
    return JSONAnswer(await _view(service, service.get(caller.user.username), caller))


@router.delete(
    "/me",
    summary="Stop the caller's workspace (its files are kept, its token revoked)",
    status_code=204,
)
async def stop(caller: Caller, service: Service) -> Response:
    assert caller.user is not None
    if service.get(caller.user.username) is not None:
        await service.stop(caller, caller.user.username)
    return Response(status_code=204)


@router.get(
    "",
    summary="Every workspace this server runs or ran (admins)",
    response_class=JSONAnswer,
    response_model=Workspaces,
    responses=problems(403),
)
async def list_all(caller: Admin, service: Service) -> JSONAnswer:
    views = [await _view(service, ws, caller) for ws in service.workspaces.values()]
    return JSONAnswer({"workspaces": sorted(views, key=lambda v: v["user"])})


@router.delete(
    "/{user}",
    summary="Stop a user's workspace (admins, or the user)",
    status_code=204,
    responses=problems(403),
)
async def stop_user(user: str, caller: Caller, service: Service) -> Response:
    await service.stop(caller, user)
    return Response(status_code=204)
