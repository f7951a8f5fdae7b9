"""/api/v1/federation/peers and /api/v1/resolve: tokens for other instances, and a relation's
target resolved to a remote twin (docs/federation.md)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Query, Request, Response
from pydantic import BaseModel, ConfigDict, Field

from twinlink.api.deps import Admin, Caller
from twinlink.api.models.problem import Problem, problems
from twinlink.api.models.twins import RemoteSummary
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.domain.errors import NotFoundError, TwinlinkError
from twinlink.federation.resolve import document_refs
from twinlink.federation.service import Federation

router = APIRouter(
    prefix="/api/v1",
    tags=["federation"],
    route_class=ExactJsonRoute,
    responses=problems(401, 422, 503),
)


async def federation(request: Request) -> Federation:
    service = request.app.state.services.federation
    if service is None:
        raise TwinlinkError("federation is not set up on this server")
    return service  # type: ignore[no-any-return]


Fed = Annotated[Federation, Depends(federation)]


async def remote_relations(request: Request, doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """The twins of other instances `doc` names (not twins of this one), by reference, with
    their name, state and where their document is: for the twin's public page."""
    services = request.app.state.services
    if services.federation is None:
        return {}
    refs = document_refs(doc)
    local = await services.registry.store.get_twins_by_dt_ids(refs) if refs else {}
    remote = [r for r in refs if r not in local]
    return await services.federation.resolver.summaries(remote) if remote else {}


class PeerToken(BaseModel):
    model_config = ConfigDict(extra="forbid")
    token: str = Field(
        min_length=1,
        max_length=4096,
        description="A token of a service account on the peer; stored sealed, never shown.",
    )
    scheme: Literal["https", "http"] = Field(
        "https", description="The peer's scheme; http only on a network you trust."
    )


class PeerOrigins(BaseModel):
    peers: list[str] = Field(description="Origins this instance has a token for.")


class PeerStored(BaseModel):
    origin: str = Field(description="The origin the token is sent to, and only to it.")


class Resolved(BaseModel):
    id: str
    remote: RemoteSummary


@router.get(
    "/federation/peers",
    summary="Origins of other instances this one has a token for (admins)",
    response_model=PeerOrigins,
    responses=problems(403),
)
async def list_peers(caller: Admin, fed: Fed) -> dict[str, Any]:
    return {"peers": fed.peers.origins()}


@router.put(
    "/federation/peers/{peer}",
    summary="Store the token sent to a peer (host[:port]) when fetching from it (admins)",
    response_model=PeerStored,
    responses=problems(403),
)
async def put_peer(peer: str, body: PeerToken, caller: Admin, fed: Fed) -> dict[str, Any]:
    return {"origin": fed.peers.put(peer, body.token, body.scheme)}


@router.delete(
    "/federation/peers/{peer}",
    summary="Forget the token of a peer (admins)",
    status_code=204,
    response_class=Response,
    responses=problems(403, 404),
)
async def delete_peer(peer: str, caller: Admin, fed: Fed) -> Response:
    if not fed.peers.delete(peer):
        raise NotFoundError(f"no token for {peer}: GET /api/v1/federation/peers lists them")
    return Response(status_code=204)


@router.get(
    "/resolve",
    summary="Fetch the twin a dt-id or URL of another instance names, now, and keep it",
    response_model=Resolved,
    responses={
        502: {"model": Problem, "description": "The other instance could not be read"},
        **problems(403),
    },
)
async def resolve(
    caller: Caller,
    fed: Fed,
    id: Annotated[str, Query(min_length=1, max_length=2048, description="a dt-id or URL")],
) -> JSONAnswer:
    return JSONAnswer(await fed.resolver.resolve(id))
