"""/api/v1/search: ranked full-text search over twins and their features."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query, Request

from twinlink.api.deps import Caller, Search
from twinlink.api.models.problem import problems
from twinlink.api.models.search import SearchAnswer
from twinlink.api.responses import JSONAnswer

router = APIRouter(prefix="/api/v1", tags=["search"])


@router.get(
    "/search",
    summary="Find twins and the features that hold what you need",
    response_class=JSONAnswer,
    response_model=SearchAnswer,
    responses=problems(401, 422, 503),
)
async def search(
    request: Request,
    caller: Caller,
    service: Search,
    q: Annotated[str, Query(max_length=256, description="words; each matches as a prefix")] = "",
    keyword: Annotated[str | None, Query(max_length=128, description="facet filter")] = None,
    limit: Annotated[int, Query(ge=1, le=200)] = 20,
    offset: Annotated[int, Query(ge=0, le=10_000)] = 0,
    remote: Annotated[
        bool | None,
        Query(
            description="also remote twins (docs/federation.md); "
            "default: TWINLINK_FEDERATION_SEARCH"
        ),
    ] = None,
) -> JSONAnswer:
    answer = await service.search(caller, q, keyword=keyword, limit=limit, offset=offset)
    services = request.app.state.services
    if services.federation is not None and (
        remote if remote is not None else request.app.state.settings.federation_search
    ):
        found = await services.federation.remote.search(q)
        answer["remote"] = [
            {"remote_id": t.id, "dt_id": t.dt_id, "name": t.name, "url": t.url,
             "state": services.federation.remote.state_of(t)}
            for t in found[:limit]
        ]  # fmt: skip
    return JSONAnswer(answer)
