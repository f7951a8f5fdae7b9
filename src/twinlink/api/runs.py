"""Lifecycle runs (docs/runs.md): a deployment's phase scripts started, followed, cancelled.

`POST /api/v1/deployments/{name}/runs` starts one (D1's DeploymentService builds its target);
`/api/v1/runs/{id}` reads one, its log (from any byte offset, while it grows, or live over
a WebSocket: the log's bytes as binary frames, then one text frame `{"state", "exit_code"}`),
and cancels it. Whoever may see the deployment's twin may read its runs; who may start and
cancel them is the `script_runners` setting's.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Annotated, Any

import orjson
from fastapi import APIRouter, Depends, Query, Request, WebSocket
from fastapi.responses import StreamingResponse
from pydantic import BaseModel, ConfigDict, Field
from starlette.websockets import WebSocketDisconnect, WebSocketState

from twinlink.api.deployments import Deployments
from twinlink.api.deps import Caller
from twinlink.api.models.problem import problems
from twinlink.api.params import OlderThan, RowId
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError
from twinlink.deploy.runs import RunService
from twinlink.domain.errors import NotFoundError, TwinlinkError
from twinlink.domain.jsontext import INT64_MAX
from twinlink.domain.runs import RunRecord
from twinlink.registry.service import RegistryService

router = APIRouter(
    prefix="/api/v1",
    tags=["runs"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
log = logging.getLogger("twinlink.runs")
AUTH_TIMEOUT_S = 10.0
CLOSE_UNAUTHORIZED = 4401
CLOSE_NOT_FOUND = 4404


async def run_service(request: Request) -> RunService:
    return _runs_of(request.app.state.services)


def _runs_of(services: Any) -> RunService:
    runs = getattr(services, "runs", None)
    if runs is None:
        raise TwinlinkError("lifecycle runs are not set up on this server")
    return runs  # type: ignore[no-any-return]


Runs = Annotated[RunService, Depends(run_service)]


class StartBody(BaseModel):
    model_config = ConfigDict(extra="forbid")

    phase: str = Field(description="the lifecycle script to run: lifecycle/<phase>")


class Run(BaseModel):
    id: int
    deployment: str
    twin: str
    phase: str
    state: str = Field(description="queued, running, succeeded, failed or cancelled")
    exit_code: int | None = Field(description="negative: killed by that signal")
    started_by: str | None
    created_ns: int
    started_ns: int | None
    ended_ns: int | None
    node: str | None
    error: str | None
    timeout_s: int
    memory_mb: int
    runner_tags: list[str]


class RunList(BaseModel):
    runs: list[Run]


async def _view(services: Any, runs: list[RunRecord]) -> list[dict[str, Any]]:
    names: dict[int, str] = {}
    for user_id in {r.started_by for r in runs if r.started_by is not None}:
        user = await services.store.get_user(user_id)
        if user is not None:
            names[user_id] = user.username
    return [_run(run, names) for run in runs]


def _run(run: RunRecord, usernames: dict[int, str]) -> dict[str, Any]:
    return {
        "id": run.id,
        "deployment": run.deployment,
        "twin": run.twin,
        "phase": run.phase,
        "state": run.state,
        "exit_code": run.exit_code,
        "started_by": usernames.get(run.started_by or -1),
        "created_ns": run.created_ns,
        "started_ns": run.started_ns,
        "ended_ns": run.ended_ns,
        "node": run.node,
        "error": run.error,
        "timeout_s": run.timeout_s,
        "memory_mb": run.memory_mb,
        "runner_tags": run.runner_tags,
    }


async def readable(registry: RegistryService, principal: Principal, run: RunRecord) -> None:
    """NotFoundError unless the caller may read the run: admins, its deployment's owner, who
    started it, and whoever may see its twin (a run one may not read is not admitted to
    exist)."""
    user = principal.user
    if principal.is_admin or (user is not None and user.id in (run.owner_id, run.started_by)):
        return
    try:
        await registry.require_twin(principal, run.twin)
    except NotFoundError:
        raise NotFoundError(f"no run {run.id}") from None


async def _readable_run(request: Request, caller: Principal, run_id: int) -> RunRecord:
    services = request.app.state.services
    run = await _runs_of(services).get(run_id)
    await readable(services.registry, caller, run)
    return run


# -- routes ------------------------------------------------------------------------------------


@router.post(
    "/deployments/{name}/runs",
    summary="Run a lifecycle phase of the deployment (its package's lifecycle/<phase>)",
    status_code=202,
    response_class=JSONAnswer,
    response_model=Run,
    responses=problems(403, 409),
)
async def start_run(
    name: str, body: StartBody, caller: Caller, deployments: Deployments, request: Request
) -> JSONAnswer:
    run = await deployments.run_phase(caller, name, body.phase)
    services = request.app.state.services
    return JSONAnswer((await _view(services, [run]))[0], status_code=202)


@router.get(
    "/deployments/{name}/runs",
    summary="The deployment's runs, newest first (all are kept)",
    response_class=JSONAnswer,
    response_model=RunList,
)
async def list_runs(
    name: str,
    caller: Caller,
    deployments: Deployments,
    runs: Runs,
    request: Request,
    before: OlderThan = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> JSONAnswer:
    record = await deployments.get(caller, name)
    found = await runs.runs(record.id, limit=limit, before_id=before)
    return JSONAnswer({"runs": await _view(request.app.state.services, found)})


@router.get(
    "/runs/{run_id}",
    summary="A run: its phase, state, exit code and times",
    response_class=JSONAnswer,
    response_model=Run,
)
async def get_run(run_id: RowId, caller: Caller, request: Request) -> JSONAnswer:
    run = await _readable_run(request, caller, run_id)
    return JSONAnswer((await _view(request.app.state.services, [run]))[0])


@router.get(
    "/runs/{run_id}/log",
    summary="The run's log (stdout and stderr) from byte `offset`, as far as it is written",
    response_class=StreamingResponse,
    responses={200: {"content": {"text/plain": {"schema": {"type": "string"}}}}},
)
async def get_log(
    run_id: RowId,
    caller: Caller,
    runs: Runs,
    request: Request,
    offset: Annotated[int, Query(ge=0, le=INT64_MAX, description="the first byte")] = 0,
) -> StreamingResponse:
    run = await _readable_run(request, caller, run_id)
    return StreamingResponse(
        runs.log(run.id, offset),
        media_type="text/plain; charset=utf-8",
        headers={"X-Run-State": run.state, "Cache-Control": "no-store"},
    )


@router.post(
    "/runs/{run_id}/cancel",
    summary="Cancel a run: its process group gets SIGTERM, then SIGKILL after 5 s",
    response_class=JSONAnswer,
    response_model=Run,
    responses=problems(403),
)
async def cancel_run(run_id: RowId, caller: Caller, runs: Runs, request: Request) -> JSONAnswer:
    await _readable_run(request, caller, run_id)
    run = await runs.cancel(caller, run_id)
    return JSONAnswer((await _view(request.app.state.services, [run]))[0])


@router.websocket("/runs/{run_id}/log/ws")
async def follow_log(websocket: WebSocket, run_id: int, offset: int = 0) -> None:
    """The log as it is written (binary frames), then `{"state", "exit_code"}` (a text frame)
    and a normal close. The token: `Authorization: Bearer` or a first text frame
    `{"op": "auth", "token": "..."}` (browsers cannot set headers)."""
    services = websocket.app.state.services
    await websocket.accept()
    try:
        principal = await _authenticate(websocket, services.auth)
        if not 1 <= run_id <= INT64_MAX or offset < 0:
            raise NotFoundError(f"no run {run_id}")
        run = await _runs_of(services).get(run_id)
        await readable(services.registry, principal, run)
    except AuthError as err:
        await _close(websocket, CLOSE_UNAUTHORIZED, str(err))
        return
    except (TwinlinkError, WebSocketDisconnect) as err:
        await _close(websocket, CLOSE_NOT_FOUND, str(err))
        return
    await _follow(websocket, _runs_of(services), run_id, offset)


async def _follow(websocket: WebSocket, runs: RunService, run_id: int, offset: int) -> None:
    """Send the log until the run ends, unless the client leaves first."""

    async def pump() -> None:
        async for chunk in runs.follow(run_id, offset):
            await websocket.send_bytes(chunk)
        run = await runs.get(run_id)
        await websocket.send_text(
            orjson.dumps({"state": run.state, "exit_code": run.exit_code}).decode()
        )
        await websocket.close(1000)

    async def gone() -> None:  # the client's frames are not read otherwise
        while (await websocket.receive())["type"] != "websocket.disconnect":
            pass

    tasks = [asyncio.create_task(pump()), asyncio.create_task(gone())]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
    finally:
        for task in tasks:
            task.cancel()
        results = await asyncio.gather(*tasks, return_exceptions=True)
    for result in results:
        if isinstance(result, Exception) and not isinstance(result, WebSocketDisconnect):
            log.warning("following a run's log failed: %s", result,
                        extra={"event": "run_follow_failed", "run": run_id})  # fmt: skip


async def _authenticate(websocket: WebSocket, auth: Any) -> Principal:
    request = ("GET", websocket.url.path)
    header = websocket.headers.get("authorization")
    if header is not None:
        scheme, _, token = header.partition(" ")
        if scheme.lower() != "bearer" or not token.strip():
            raise AuthError("the Authorization header must be 'Bearer <token>'")
        return await auth.authenticate(token.strip(), request)  # type: ignore[no-any-return]
    try:
        frame = await asyncio.wait_for(websocket.receive(), AUTH_TIMEOUT_S)
    except TimeoutError:
        raise AuthError(f"no token within {AUTH_TIMEOUT_S:.0f} s") from None
    if frame["type"] == "websocket.disconnect":
        raise WebSocketDisconnect(frame.get("code", 1000))
    try:
        message = orjson.loads(frame.get("text") or frame.get("bytes") or b"")
    except orjson.JSONDecodeError:
        message = None
    sent = message.get("token") if isinstance(message, dict) else None
    if not isinstance(sent, str) or not sent:
        raise AuthError('send the token first: {"op": "auth", "token": "tl_..."}')
    return await auth.authenticate(sent, request)  # type: ignore[no-any-return]


async def _close(websocket: WebSocket, code: int, reason: str) -> None:
    if websocket.application_state == WebSocketState.DISCONNECTED:
        return
    with contextlib.suppress(RuntimeError, WebSocketDisconnect):
        await websocket.close(code, reason[:120])
