"""/api/v1/remote-twins: DT documents of other instances kept here read-only, and the import
of a Twinbase site (or another twinlink) as remote twins (docs/federation.md, "Mirroring a
Twinbase site"). Any signed-in user reads them; admins import, refresh and delete, since
those make the server fetch from other hosts."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Query, Request, Response
from pydantic import BaseModel, ConfigDict, Field

from twinlink.api.deps import Admin, Caller
from twinlink.api.models.problem import problems
from twinlink.api.params import RowId
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.domain.commands import iso_time
from twinlink.domain.errors import TwinlinkError
from twinlink.domain.remote import RemoteTwin
from twinlink.federation.remote import RemoteTwins
from twinlink.federation.twinbase import import_site

router = APIRouter(
    prefix="/api/v1",
    tags=["remote twins"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422),
)
FETCHING = problems(403, 502)  # 502: the other instance could not be read


def remote_twins(request: Request) -> RemoteTwins:
    federation = request.app.state.services.federation
    if federation is None:
        raise TwinlinkError("federation is not set up on this server")
    return federation.remote  # type: ignore[no-any-return]


Remote = Annotated[RemoteTwins, Depends(remote_twins)]


# -- bodies and answers ----------------------------------------------------------------------


class ImportSite(BaseModel):
    model_config = ConfigDict(extra="forbid")

    url: str = Field(
        min_length=1,
        max_length=2000,
        description="The site's root (its index.json is read) or the URL of its index.json",
    )


class RemoteTwinSummary(BaseModel):
    id: int
    dt_id: str = Field(description="the document's dt-id (or id), else the URL it came from")
    url: str = Field(description="where the document was fetched: its hosting-iri")
    name: str
    source: str = Field(description="the site imported, or `relation`")
    state: str = Field(description="reachable, stale (the last check failed or is old) or gone")
    error: str = Field(description="why the last check failed")
    fetched_at: str = Field(description="when the copy was fetched")
    checked_at: str = Field(description="when the other instance was last asked")


class RemoteTwinView(RemoteTwinSummary):
    etag: str | None
    last_modified: str | None
    document: dict[str, Any] = Field(description="the DT document as fetched, read-only")


class RemoteTwinList(BaseModel):
    remote_twins: list[RemoteTwinSummary]


class ImportFailure(BaseModel):
    url: str
    name: str
    error: str


class ImportResult(BaseModel):
    source: str
    imported: list[RemoteTwinSummary]
    failed: list[ImportFailure] = Field(description="twins that could not be fetched, and why")


def _summary(remote: RemoteTwins, twin: RemoteTwin) -> dict[str, Any]:
    return {
        "id": twin.id,
        "dt_id": twin.dt_id,
        "url": twin.url,
        "name": twin.name,
        "source": twin.source,
        "state": remote.state_of(twin),
        "error": twin.error,
        "fetched_at": iso_time(twin.fetched_ns),
        "checked_at": iso_time(twin.checked_ns),
    }


def _view(remote: RemoteTwins, twin: RemoteTwin) -> JSONAnswer:
    return JSONAnswer(
        {**_summary(remote, twin), "etag": twin.etag, "last_modified": twin.last_modified,
         "document": twin.document}
    )  # fmt: skip


# -- routes ------------------------------------------------------------------------------------


@router.get(
    "/remote-twins",
    summary="Remote twins: documents of other instances kept here, by name",
    response_class=JSONAnswer,
    response_model=RemoteTwinList,
)
async def list_remote_twins(
    _: Caller,
    remote: Remote,
    q: Annotated[
        str | None, Query(max_length=200, description="only those whose text holds this")
    ] = None,
) -> JSONAnswer:
    twins = await remote.list(q)
    return JSONAnswer({"remote_twins": [_summary(remote, t) for t in twins]})


@router.get(
    "/remote-twins/{remote_id}",
    summary="A remote twin with its document",
    response_class=JSONAnswer,
    response_model=RemoteTwinView,
)
async def get_remote_twin(remote_id: RowId, _: Caller, remote: Remote) -> JSONAnswer:
    return _view(remote, await remote.get(remote_id))


@router.post(
    "/remote-twins/import",
    summary="Mirror a Twinbase site (or another twinlink) as remote twins: its index.json, "
    "then each twin's document; importing again updates them",
    response_class=JSONAnswer,
    response_model=ImportResult,
    responses=FETCHING,
)
async def import_remote_twins(body: ImportSite, _: Admin, remote: Remote) -> JSONAnswer:
    result = await import_site(remote, body.url)
    return JSONAnswer(
        {
            "source": result.source,
            "imported": [_summary(remote, t) for t in result.imported],
            "failed": [{"url": f.url, "name": f.name, "error": f.error} for f in result.failed],
        }
    )


@router.post(
    "/remote-twins/{remote_id}/refresh",
    summary="Fetch a remote twin again from where it was found (a 304 keeps the copy)",
    response_class=JSONAnswer,
    response_model=RemoteTwinView,
    responses=FETCHING,
)
async def refresh_remote_twin(remote_id: RowId, _: Admin, remote: Remote) -> JSONAnswer:
    return _view(remote, await remote.refresh(remote_id))


@router.delete(
    "/remote-twins/{remote_id}",
    summary="Forget a remote twin (a relation to it fetches it again)",
    status_code=204,
    response_class=Response,
    responses=problems(403),
)
async def delete_remote_twin(remote_id: RowId, _: Admin, remote: Remote) -> Response:
    await remote.delete(remote_id)
    return Response(status_code=204)
