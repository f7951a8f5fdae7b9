"""/api/v1/blueprints, /api/v1/twins/{slug}/processors and /api/v1/twins/{slug}/fmus."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Query, Request, Response

from twinlink.api.deps import Caller
from twinlink.api.models.problem import problems
from twinlink.api.models.processors import (
    Blueprint,
    Blueprints,
    Fmus,
    FmuView,
    ProcessorEvents,
    ProcessorLogs,
    Processors,
    ProcessorView,
)
from twinlink.api.params import OlderThan
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.processors.checks import uploads_of
from twinlink.processors.fmus import FmuService, fmu_view
from twinlink.processors.service import ProcessorService
from twinlink.processors.spec import ProcessorSpec

router = APIRouter(
    prefix="/api/v1",
    tags=["processors"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
# Changing a processor or an FMU: editors only (403), a name or FMU may be taken or in use.
CHANGING = problems(403, 409, 507)


async def processor_service(request: Request) -> ProcessorService:
    return request.app.state.services.processors  # type: ignore[no-any-return]


async def fmu_service(request: Request) -> FmuService:
    return request.app.state.services.fmus  # type: ignore[no-any-return]


ProcessorsService = Annotated[ProcessorService, Depends(processor_service)]
FmusService = Annotated[FmuService, Depends(fmu_service)]


@router.get(
    "/blueprints",
    summary="Blueprints with their documentation and parameter JSON schema",
    response_class=JSONAnswer,
    response_model=Blueprints,
)
async def list_blueprints(_: Caller, processors: ProcessorsService) -> JSONAnswer:
    return JSONAnswer({"blueprints": processors.blueprints()})


@router.get(
    "/blueprints/{name}",
    summary="One blueprint",
    response_class=JSONAnswer,
    response_model=Blueprint,
)
async def get_blueprint(name: str, _: Caller, processors: ProcessorsService) -> JSONAnswer:
    return JSONAnswer(processors.blueprint(name))


@router.get(
    "/twins/{slug}/processors",
    summary="The twin's processors with state and figures (viewers)",
    response_class=JSONAnswer,
    response_model=Processors,
    responses=problems(403),
)
async def list_processors(slug: str, caller: Caller, processors: ProcessorsService) -> JSONAnswer:
    return JSONAnswer({"processors": await processors.list_processors(caller, slug)})


@router.post(
    "/twins/{slug}/processors",
    summary="Create a processor (editors); it starts at once unless `enabled` is false",
    response_class=JSONAnswer,
    status_code=201,
    response_model=ProcessorView,
    responses=CHANGING,
)
async def create_processor(
    slug: str, body: ProcessorSpec, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    made = await processors.create(caller, slug, body.model_dump(mode="json", exclude_unset=True))
    return JSONAnswer(made, status_code=201)


@router.get(
    "/twins/{slug}/processors/{name}",
    summary="A processor: configuration, state, figures, its blueprint's inputs and outputs",
    response_class=JSONAnswer,
    response_model=ProcessorView,
    responses=problems(403),
)
async def get_processor(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    return JSONAnswer(await processors.get(caller, slug, name))


@router.patch(
    "/twins/{slug}/processors/{name}",
    summary="Change a processor (editors). New `params` alone are applied to the running "
    "worker, keeping its state where the blueprint can (`kept_state`); other changes restart it",
    response_class=JSONAnswer,
    response_model=ProcessorView,
    responses=CHANGING,
)
async def update_processor(
    slug: str,
    name: str,
    caller: Caller,
    processors: ProcessorsService,
    changes: Annotated[dict[str, Any], Body(description="fields of the processor to change")],
) -> JSONAnswer:
    return JSONAnswer(await processors.update(caller, slug, name, changes))


@router.post(
    "/twins/{slug}/processors/{name}/start",
    summary="Start (editors)",
    response_class=JSONAnswer,
    response_model=ProcessorView,
    responses=CHANGING,
)
async def start_processor(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    return JSONAnswer(await processors.set_enabled(caller, slug, name, True))


@router.post(
    "/twins/{slug}/processors/{name}/stop",
    summary="Stop gracefully (editors)",
    response_class=JSONAnswer,
    response_model=ProcessorView,
    responses=CHANGING,
)
async def stop_processor(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    return JSONAnswer(await processors.set_enabled(caller, slug, name, False))


@router.post(
    "/twins/{slug}/processors/{name}/restart",
    summary="Restart its worker (editors)",
    response_class=JSONAnswer,
    response_model=ProcessorView,
    responses=CHANGING,
)
async def restart_processor(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    return JSONAnswer(await processors.restart(caller, slug, name))


@router.delete(
    "/twins/{slug}/processors/{name}",
    summary="Delete (editors)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_processor(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> Response:
    await processors.delete(caller, slug, name)
    return Response(status_code=204)


@router.get(
    "/twins/{slug}/processors/{name}/events",
    summary="What happened: started, crashed (with the cause), memory limit, alarms (newest first)",
    response_class=JSONAnswer,
    response_model=ProcessorEvents,
    responses=problems(403),
)
async def processor_events(
    slug: str,
    name: str,
    caller: Caller,
    processors: ProcessorsService,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
    before: OlderThan = None,
    kind: Annotated[str | None, Query(description="only events of this kind")] = None,
) -> JSONAnswer:
    events = await processors.events(caller, slug, name, limit, before, kind)
    return JSONAnswer(
        {
            "events": [
                {
                    "id": e.id,
                    "time_ns": e.time_ns,
                    "kind": e.kind,
                    "message": e.message,
                    "data": e.data,
                }
                for e in events
            ]
        }
    )


@router.get(
    "/twins/{slug}/processors/{name}/logs",
    summary="The last lines its worker printed (its own and its native code's output)",
    response_class=JSONAnswer,
    response_model=ProcessorLogs,
    responses=problems(403),
)
async def processor_logs(
    slug: str, name: str, caller: Caller, processors: ProcessorsService
) -> JSONAnswer:
    lines = await processors.logs(caller, slug, name)
    return JSONAnswer({"lines": [{"time_ns": t, "text": text} for t, text in lines]})


# -- FMUs -----------------------------------------------------------------------------------


@router.put(
    "/twins/{slug}/fmus/{name}",
    summary="Upload an FMU (editors): the file as the body; checked with FMPy, replaced if "
    "it exists",
    response_class=JSONAnswer,
    status_code=201,
    response_model=FmuView,
    responses={**CHANGING, **problems(413)},
    openapi_extra={
        "requestBody": {
            "required": True,
            "content": {
                "application/octet-stream": {"schema": {"type": "string", "format": "binary"}}
            },
        }
    },
)
async def upload_fmu(
    slug: str, name: str, request: Request, caller: Caller, fmus: FmusService
) -> JSONAnswer:
    record = await fmus.upload(caller, slug, name, request.stream())
    return JSONAnswer(fmu_view(record, variables=True), status_code=201)


@router.get(
    "/twins/{slug}/fmus",
    summary="The twin's FMUs (viewers)",
    response_class=JSONAnswer,
    response_model=Fmus,
    responses=problems(403),
)
async def list_fmus(slug: str, caller: Caller, fmus: FmusService) -> JSONAnswer:
    return JSONAnswer({"fmus": [fmu_view(r) for r in await fmus.list_fmus(caller, slug)]})


@router.get(
    "/twins/{slug}/fmus/{name}",
    summary="An FMU and its variables: causality, type, unit, start, min, max (viewers)",
    response_class=JSONAnswer,
    response_model=FmuView,
    responses=problems(403),
)
async def get_fmu(slug: str, name: str, caller: Caller, fmus: FmusService) -> JSONAnswer:
    return JSONAnswer(fmu_view(await fmus.get(caller, slug, name), variables=True))


@router.delete(
    "/twins/{slug}/fmus/{name}",
    summary="Delete an FMU (editors)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_fmu(
    slug: str, name: str, caller: Caller, fmus: FmusService, processors: ProcessorsService
) -> Response:
    users = [
        p["name"]
        for p in await processors.list_processors(caller, slug)
        if (p["blueprint"] == "fmu" and p.get("params", {}).get("fmu") == name)
        or name in uploads_of(processors.catalog, p["blueprint"], p.get("params", {}))
    ]
    await fmus.delete(caller, slug, name, users)
    return Response(status_code=204)
