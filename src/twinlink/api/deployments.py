"""/api/v1/deployments: twin packages planned, applied and taken through their lifecycle
(docs/deployments.md). The runs of their lifecycle phases are api/runs.py's."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Query, Request
from pydantic import BaseModel, ConfigDict, Field

from twinlink.api.deps import Caller
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.deploy.service import Created, DeploymentService
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import InvalidInputError, TwinlinkError

router = APIRouter(
    prefix="/api/v1",
    tags=["deployments"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
# Changing a deployment: its twin's owners (403); a name may be taken, a state wrong (409).
CHANGING = problems(403, 409, 507)
DRY_RUN = Query(description="answer the plan only; nothing is stored or changed")


async def deployment_service(request: Request) -> DeploymentService:
    service = request.app.state.services.deployments
    if service is None:
        raise TwinlinkError("deployments are not set up on this server")
    return service  # type: ignore[no-any-return]


Deployments = Annotated[DeploymentService, Depends(deployment_service)]


# -- bodies and answers ----------------------------------------------------------------------


class CreateBody(BaseModel):
    model_config = ConfigDict(extra="forbid")

    package: str = Field(description="a `twins` asset: NAME[@REF], SCOPE/twins/NAME[@REF] or lib:")
    name: str = Field(description="the deployment's and its twin's name (a slug)")
    parameters: dict[str, Any] = Field(default_factory=dict)
    scope: str | None = Field(None, description="look the package up in this scope only")
    start: bool = Field(False, description="start it once created")
    state: str | None = Field(None, description="`planned`: store it without applying it")


class ChangeBody(BaseModel):
    model_config = ConfigDict(extra="forbid")

    parameters: dict[str, Any] | None = Field(None, description="those to change; others kept")
    package: str | None = Field(None, description="another version of the package")


class TerminateBody(BaseModel):
    model_config = ConfigDict(extra="forbid")

    purge: bool = Field(False, description="delete the twin too, with its history")


class Resources(BaseModel):
    twin: str | None
    devices: list[str]
    processors: list[str]
    connectors: list[str]
    services: list[str]


class Deployment(BaseModel):
    id: int
    name: str
    package: str = Field(description="the pinned ref of the package version deployed")
    package_ref: str = Field(description="the package as asked for")
    parameters: dict[str, Any]
    state: str = Field(description="planned, applying, created, running, stopped, terminated "
                       "or failed")  # fmt: skip
    twin: str
    resources: Resources
    created_by: str | None
    created_ns: int
    updated_ns: int
    error: str | None


class DeploymentList(BaseModel):
    deployments: list[Deployment]


class PlanEntry(BaseModel):
    type: str
    name: str
    spec: dict[str, Any] | None = None
    changes: list[dict[str, Any]] | None = None


class Plan(BaseModel):
    create: list[PlanEntry]
    update: list[PlanEntry]
    delete: list[PlanEntry]
    keep: list[PlanEntry]


class PlanAnswer(BaseModel):
    plan: Plan


class Applied(BaseModel):
    deployment: Deployment
    plan: Plan
    device_tokens: dict[str, str] = Field(description="new devices' tokens, shown once")


async def _view(
    service: DeploymentService, records: list[DeploymentRecord]
) -> list[dict[str, Any]]:
    names: dict[int, str] = {}
    for user_id in {r.created_by for r in records if r.created_by is not None}:
        user = await service.store.get_user(user_id)
        if user is not None:
            names[user_id] = user.username
    return [_deployment(r, names) for r in records]


def _deployment(record: DeploymentRecord, usernames: dict[int, str]) -> dict[str, Any]:
    return {
        "id": record.id,
        "name": record.name,
        "package": record.package,
        "package_ref": record.package_ref,
        "parameters": record.parameters,
        "state": record.state,
        "twin": record.twin,
        "resources": record.resources(),
        "created_by": usernames.get(record.created_by or -1),
        "created_ns": record.created_ns,
        "updated_ns": record.updated_ns,
        "error": record.error,
    }


async def _applied(service: DeploymentService, made: Created, status: int = 200) -> JSONAnswer:
    body = {
        "deployment": (await _view(service, [made.record]))[0],
        "plan": made.plan.view(),
        "device_tokens": made.device_tokens,
    }
    return JSONAnswer(body, status_code=status)


# -- routes ------------------------------------------------------------------------------------


@router.get(
    "/deployments",
    summary="The deployments the caller may see (those of twins they see), newest first",
    response_class=JSONAnswer,
    response_model=DeploymentList,
)
async def list_deployments(caller: Caller, deployments: Deployments) -> JSONAnswer:
    records = await deployments.list(caller)
    return JSONAnswer({"deployments": await _view(deployments, records)})


@router.post(
    "/deployments",
    summary="Deploy a twin package: plan, then apply all or nothing (201), or only the plan "
    "(`dry_run`, 200)",
    response_class=JSONAnswer,
    status_code=201,
    response_model=Applied,
    responses={**CHANGING, 200: {"model": PlanAnswer, "description": "The plan (`dry_run`)"}},
)
async def create_deployment(
    body: CreateBody,
    caller: Caller,
    deployments: Deployments,
    dry_run: Annotated[bool, DRY_RUN] = False,
) -> JSONAnswer:
    if body.state not in (None, "planned", "created", "running"):
        raise _bad_state(body.state)
    if dry_run:
        plan = await deployments.plan(caller, body.package, body.name, body.parameters, body.scope)
        return JSONAnswer({"plan": plan.view()})
    made = await deployments.create(
        caller, body.package, body.name, body.parameters, body.scope,
        start=body.start or body.state == "running", planned=body.state == "planned",
    )  # fmt: skip
    return await _applied(deployments, made, 201)


def _bad_state(state: str | None) -> TwinlinkError:
    return InvalidInputError(f"`state` is planned, created or running, not {state!r}")


@router.get(
    "/deployments/{name}",
    summary="A deployment: its package, parameters, state and what it made",
    response_class=JSONAnswer,
    response_model=Deployment,
)
async def get_deployment(name: str, caller: Caller, deployments: Deployments) -> JSONAnswer:
    return JSONAnswer((await _view(deployments, [await deployments.get(caller, name)]))[0])


@router.patch(
    "/deployments/{name}",
    summary="Reconfigure: new parameters (others kept) and/or package version; the diff plan, "
    "applied unless `dry_run` (unchanged resources are not touched)",
    response_class=JSONAnswer,
    response_model=Applied,
    responses=CHANGING,
)
async def change_deployment(
    name: str,
    body: ChangeBody,
    caller: Caller,
    deployments: Deployments,
    dry_run: Annotated[bool, DRY_RUN] = False,
) -> JSONAnswer:
    made = await deployments.reconfigure(caller, name, body.parameters, body.package, dry_run)
    return await _applied(deployments, made)


@router.post(
    "/deployments/{name}/create",
    summary="Apply a planned deployment",
    response_class=JSONAnswer,
    response_model=Applied,
    responses=CHANGING,
)
async def create_planned(name: str, caller: Caller, deployments: Deployments) -> JSONAnswer:
    return await _applied(deployments, await deployments.create_planned(caller, name))


@router.post(
    "/deployments/{name}/start",
    summary="Start: its processors and connectors run, and its `execute` phase",
    response_class=JSONAnswer,
    response_model=Deployment,
    responses=CHANGING,
)
async def start_deployment(name: str, caller: Caller, deployments: Deployments) -> JSONAnswer:
    return await _one(deployments, await deployments.start(caller, name))


@router.post(
    "/deployments/{name}/stop",
    summary="Stop: its processors and connectors stop, and a running `execute`; the twin stays",
    response_class=JSONAnswer,
    response_model=Deployment,
    responses=CHANGING,
)
async def stop_deployment(name: str, caller: Caller, deployments: Deployments) -> JSONAnswer:
    return await _one(deployments, await deployments.stop(caller, name))


@router.post(
    "/deployments/{name}/terminate",
    summary="Terminate: remove its devices (their tokens), processors, connectors and "
    "services; the twin and its history stay unless `purge`",
    response_class=JSONAnswer,
    response_model=Deployment,
    responses=CHANGING,
)
async def terminate_deployment(
    name: str, caller: Caller, deployments: Deployments, body: TerminateBody | None = None
) -> JSONAnswer:
    purge = body.purge if body is not None else False
    return await _one(deployments, await deployments.terminate(caller, name, purge))


async def _one(service: DeploymentService, record: DeploymentRecord) -> JSONAnswer:
    return JSONAnswer((await _view(service, [record]))[0])
