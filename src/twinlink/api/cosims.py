"""/api/v1/cosims: co-simulations created from an uploaded file (a Maestro multi-model, a YAML
system, an SSP archive, or a folder as a zip or tar), run in a process of their own, their
results as Maestro's outputs.csv and as columns for a chart (docs/cosim.md, "The API")."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Query, Request, Response
from fastapi.responses import FileResponse
from pydantic import BaseModel, ConfigDict, Field

from twinlink.api.deps import Caller
from twinlink.api.models.problem import problems
from twinlink.api.params import RowId
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.cosim.params import MAX_FACTOR
from twinlink.cosim.service import CosimService
from twinlink.cosim.upload import MEDIA
from twinlink.domain.commands import iso_time
from twinlink.domain.cosims import CosimRecord
from twinlink.domain.errors import NotFoundError, TwinlinkError

router = APIRouter(
    prefix="/api/v1",
    tags=["cosims"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
CHANGING = problems(403, 409)
BINARY = {"schema": {"type": "string", "format": "binary"}}
UPLOAD = {
    "requestBody": {
        "required": True,
        "description": "The co-simulation file: a Maestro multi-model (JSON), twinlink's "
        "YAML form, an SSP archive (a zip with SystemStructure.ssd at its root), or a folder "
        "as a zip, tar or tgz holding one .json/.yaml document at its top level beside its "
        "FMUs.",
        "content": dict.fromkeys(MEDIA, BINARY),
    }
}


async def cosim_service(request: Request) -> CosimService:
    service = request.app.state.services.cosims
    if service is None:
        raise TwinlinkError("co-simulations are not set up on this server")
    return service  # type: ignore[no-any-return]


Cosims = Annotated[CosimService, Depends(cosim_service)]


# -- bodies and answers ----------------------------------------------------------------------


class CosimStart(BaseModel):
    model_config = ConfigDict(extra="forbid")

    mode: str | None = Field(None, description="batch or realtime; the last one's if not given")
    factor: float | None = Field(
        None, gt=0, le=MAX_FACTOR, description="realtime: 1.0 = wall clock, 2.0 = twice as fast"
    )


class CosimInstance(BaseModel):
    name: str
    fmu: str
    kind: str = Field(description="co-simulation, model-exchange or python")
    isolated: bool


class CosimConnection(BaseModel):
    source: str
    target: str


class CosimAlgorithm(BaseModel):
    kind: str = Field(description="fixed-step or var-step")
    size: float
    min_size: float | None
    max_size: float | None
    master: str = Field(description="jacobi or gauss-seidel")


class CosimSystem(BaseModel):
    source: str = Field(description="the format it was read from: maestro, ssp or yaml")
    instances: list[CosimInstance]
    connections: list[CosimConnection]
    algorithm: CosimAlgorithm
    start_time: float
    end_time: float | None
    loops: list[list[str]] = Field(description="algebraic loops, each as its ports in order")


class Cosim(BaseModel):
    id: int
    name: str
    owner: str | None
    twin: str | None = Field(description="the twin whose history gets the results")
    prefix: str = Field(description="of the signals written into the twin's history")
    stream: str = Field(description="the twin's stream they go to")
    mode: str = Field(description="batch or realtime")
    factor: float
    state: str = Field(description="created, running, finished, stopped or failed")
    progress: float = Field(description="0 to 1")
    sim_time: float | None
    message: str = Field(description="why it failed or ended early")
    created_at: str
    started_at: str | None
    ended_at: str | None
    system: CosimSystem
    columns: list[str] = Field(description="the results' columns, time first")
    rows: int


class CosimList(BaseModel):
    cosims: list[Cosim]


class CosimResults(BaseModel):
    columns: list[str]
    data: list[list[float | None]] = Field(description="column by column (uPlot's shape)")


def _view(record: CosimRecord, owner: str | None) -> dict[str, Any]:
    return {
        "id": record.id,
        "name": record.name,
        "owner": owner,
        "twin": record.twin,
        "prefix": record.prefix,
        "stream": record.stream,
        "mode": record.mode,
        "factor": record.factor,
        "state": record.state,
        "progress": record.progress,
        "sim_time": record.sim_time,
        "message": record.message,
        "created_at": iso_time(record.created_ns),
        "started_at": iso_time(record.started_ns) if record.started_ns else None,
        "ended_at": iso_time(record.ended_ns) if record.ended_ns else None,
        "system": record.system,
        "columns": record.columns,
        "rows": record.rows,
    }


async def _one(cosims: CosimService, record: CosimRecord, status: int = 200) -> JSONAnswer:
    return JSONAnswer(_view(record, await cosims.owner_name(record)), status_code=status)


# -- routes ------------------------------------------------------------------------------------

TwinParam = Annotated[
    str | None, Query(max_length=100, description="results into this twin's history (editors)")
]
StreamParam = Annotated[
    str | None, Query(max_length=64, description="the twin's stream (default cosim)")
]


@router.post(
    "/cosims",
    summary="Create a co-simulation from a file or folder (the body); its FMUs resolve inside "
    "the folder, in the library (lib:...) or among the twin's uploaded FMUs",
    response_class=JSONAnswer,
    status_code=201,
    response_model=Cosim,
    responses={**CHANGING, **problems(413, 507)},
    openapi_extra=UPLOAD,
)
async def create_cosim(
    request: Request,
    caller: Caller,
    cosims: Cosims,
    name: Annotated[str | None, Query(max_length=100, description="its name")] = None,
    twin: TwinParam = None,
    mode: Annotated[str, Query(description="batch or realtime")] = "batch",
    factor: Annotated[
        float, Query(gt=0, le=MAX_FACTOR, description="realtime: 1.0 = wall clock")
    ] = 1.0,
    prefix: Annotated[str, Query(max_length=64, description="of the signals")] = "",
    stream: StreamParam = None,
) -> JSONAnswer:
    record = await cosims.create(
        caller, request.stream(), request.headers.get("content-type", ""), name=name,
        twin=twin, mode=mode, factor=factor, prefix=prefix, stream=stream,
    )  # fmt: skip
    return await _one(cosims, record, 201)


@router.get(
    "/cosims",
    summary="The caller's co-simulations (every one for admins), newest first",
    response_class=JSONAnswer,
    response_model=CosimList,
)
async def list_cosims(caller: Caller, cosims: Cosims) -> JSONAnswer:
    records = await cosims.list_cosims(caller)
    names: dict[int, str | None] = {}
    for record in records:
        if record.owner_id is not None and record.owner_id not in names:
            names[record.owner_id] = await cosims.owner_name(record)
    return JSONAnswer({"cosims": [_view(r, names.get(r.owner_id or -1)) for r in records]})


@router.get(
    "/cosims/{cosim_id}",
    summary="A co-simulation: its system, state and progress",
    response_class=JSONAnswer,
    response_model=Cosim,
)
async def get_cosim(cosim_id: RowId, caller: Caller, cosims: Cosims) -> JSONAnswer:
    return await _one(cosims, await cosims.get(caller, cosim_id))


@router.delete(
    "/cosims/{cosim_id}",
    summary="Delete a co-simulation with its files and results (409 while it runs)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_cosim(cosim_id: RowId, caller: Caller, cosims: Cosims) -> Response:
    await cosims.delete(caller, cosim_id)
    return Response(status_code=204)


@router.post(
    "/cosims/{cosim_id}/start",
    summary="Run it (again: new results); the body may change its mode and factor",
    response_class=JSONAnswer,
    response_model=Cosim,
    responses=CHANGING,
)
async def start_cosim(
    cosim_id: RowId, caller: Caller, cosims: Cosims, body: CosimStart | None = None
) -> JSONAnswer:
    mode, factor = (body.mode, body.factor) if body is not None else (None, None)
    return await _one(cosims, await cosims.start(caller, cosim_id, mode, factor))


@router.post(
    "/cosims/{cosim_id}/stop",
    summary="Stop its run after the current step (the rows so far kept)",
    response_class=JSONAnswer,
    response_model=Cosim,
    responses=CHANGING,
)
async def stop_cosim(cosim_id: RowId, caller: Caller, cosims: Cosims) -> JSONAnswer:
    return await _one(cosims, await cosims.stop(caller, cosim_id))


@router.get(
    "/cosims/{cosim_id}/results.csv",
    summary="The latest run's results as Maestro's outputs.csv (as far as written)",
    response_class=FileResponse,
    responses={200: {"content": {"text/csv": BINARY}}},
)
async def results_csv(cosim_id: RowId, caller: Caller, cosims: Cosims) -> FileResponse:
    record = await cosims.get(caller, cosim_id)
    path = cosims.results_path(record)
    if not path.is_file():
        raise NotFoundError(f"co-simulation {cosim_id} has no results yet: start it")
    return FileResponse(path, media_type="text/csv", filename=f"cosim-{cosim_id}-outputs.csv")


@router.get(
    "/cosims/{cosim_id}/results",
    summary="The latest run's results for a chart: its columns, at most `max_points` rows "
    "picked evenly, column by column",
    response_class=JSONAnswer,
    response_model=CosimResults,
)
async def results(
    cosim_id: RowId,
    caller: Caller,
    cosims: Cosims,
    max_points: Annotated[int, Query(ge=2, le=100_000)] = 2000,
) -> JSONAnswer:
    return JSONAnswer(await cosims.results(caller, cosim_id, max_points))
