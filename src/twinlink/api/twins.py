"""/api/v1/twins: the twin registry."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request, Response
from pydantic import BaseModel, Field

from twinlink.api._body import DOCUMENT_BODY, read_documents
from twinlink.api.deps import Caller, Registry
from twinlink.api.responses import JSONAnswer
from twinlink.auth.rights import has_role, may_see_level
from twinlink.domain.errors import ForbiddenError
from twinlink.domain.records import ROLES, TwinRecord
from twinlink.domain.yamlsource import dump_yaml
from twinlink.registry.build import human_time
from twinlink.registry.service import Applied, RegistryService

router = APIRouter(prefix="/api/v1", tags=["twins"])
YAML = "application/yaml"


def summary(
    reg: RegistryService, twin: TwinRecord, levels: list[str] | None = None
) -> dict[str, Any]:
    return {
        "slug": twin.slug,
        "id": twin.dt_id,
        "name": twin.name,
        "url": reg.canonical_url(twin.slug),
        "created": human_time(twin.created_ns),
        "modified": human_time(twin.modified_ns),
        "levels": levels if levels is not None else twin.levels,
    }


def _applied(reg: RegistryService, a: Applied) -> dict[str, Any]:
    return {**summary(reg, a.twin, a.levels), "outcome": a.outcome}


@router.get("/twins", summary="List the twins the caller may see")
async def list_twins(
    caller: Caller,
    reg: Registry,
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    cursor: Annotated[str | None, Query(description="`next_cursor` of the previous page")] = None,
    keyword: Annotated[
        str | None, Query(description="only twins with a feature of this keyword")
    ] = None,
    q: Annotated[str | None, Query(description="only twins whose name contains this text")] = None,
    mine: Annotated[bool, Query(description="only twins the caller has a role on")] = False,
) -> dict[str, Any]:
    twins = await reg.store.list_twins(
        caller.visibility,
        limit=limit + 1,
        after_slug=cursor,
        keyword=keyword,
        name_contains=q,
        role_user_id=caller.user.id if mine and caller.user else None,
    )
    page = twins[:limit]
    return {
        "items": [summary(reg, t) for t in page],
        "next_cursor": page[-1].slug if len(twins) > limit else None,
    }


@router.post("/twins", status_code=201, summary="Create a twin", openapi_extra=DOCUMENT_BODY)
async def create_twin(
    request: Request,
    caller: Caller,
    reg: Registry,
    slug: Annotated[str | None, Query(description="slug to use instead of the derived one")] = None,
) -> dict[str, Any]:
    docs = await read_documents(request)
    result = await reg.apply(caller, docs, slug=slug, mode="create")
    return _applied(reg, result[0])


@router.post(
    "/apply",
    summary="Create or update twins from documents (idempotent)",
    openapi_extra=DOCUMENT_BODY,
)
async def apply(request: Request, caller: Caller, reg: Registry) -> dict[str, Any]:
    docs = await read_documents(request)
    results = await reg.apply(caller, docs)
    return {"results": [_applied(reg, a) for a in results]}


@router.get(
    "/twins/{slug}",
    summary="A twin and its document as the caller may see it",
    response_class=JSONAnswer,
)
async def get_twin(slug: str, caller: Caller, reg: Registry) -> JSONAnswer:
    twin, role, document = await reg.document(caller, slug)
    levels = [lv for lv in twin.levels if may_see_level(caller, role, lv)]
    return JSONAnswer(
        {
            **summary(reg, twin, levels),
            "role": "admin" if caller.is_admin else role,
            "document": document,
        }
    )


@router.put("/twins/{slug}", summary="Update a twin's document parts", openapi_extra=DOCUMENT_BODY)
async def update_twin(
    slug: str,
    request: Request,
    caller: Caller,
    reg: Registry,
    dry_run: Annotated[
        bool, Query(description="check the documents and the rights; store nothing")
    ] = False,
) -> dict[str, Any]:
    docs = await read_documents(request)
    result = await reg.apply(caller, docs, slug=slug, mode="update", dry_run=dry_run)
    answer = _applied(reg, result[0])
    return {**answer, "dry_run": True} if dry_run else answer


@router.delete("/twins/{slug}", summary="Delete a twin (and, with cascade, its descendants)")
async def delete_twin(
    slug: str,
    caller: Caller,
    reg: Registry,
    cascade: Annotated[bool, Query(description="also delete every descendant")] = False,
) -> dict[str, Any]:
    return {"deleted": await reg.delete(caller, slug, cascade)}


@router.get("/twins/{slug}/parts", summary="The privacy parts of a twin the caller may see")
async def list_parts(slug: str, caller: Caller, reg: Registry) -> dict[str, Any]:
    twin, role = await reg.require_twin(caller, slug)
    return {"levels": [lv for lv in twin.levels if may_see_level(caller, role, lv)]}


@router.get(
    "/twins/{slug}/parts/{level}",
    summary="One privacy part, as stored (JSON, or YAML with format=yaml)",
    responses={200: {"content": {"application/json": {}, YAML: {}}}},
)
async def get_part(
    slug: str,
    level: str,
    caller: Caller,
    reg: Registry,
    format: Annotated[Literal["json", "yaml"], Query(description="answer format")] = "json",
) -> Any:
    part = await reg.part(caller, slug, level)
    if format == "yaml":
        return Response(dump_yaml(part), media_type=YAML + "; charset=utf-8")
    return part


@router.delete("/twins/{slug}/parts/{level}", summary="Remove one privacy part")
async def delete_part(slug: str, level: str, caller: Caller, reg: Registry) -> dict[str, Any]:
    twin = await reg.delete_part(caller, slug, level)
    return summary(reg, twin)


@router.get("/twins/{slug}/relations", summary="Descendants (down) or ancestors (up) to a depth")
async def relations(
    slug: str,
    caller: Caller,
    reg: Registry,
    direction: Literal["down", "up"] = "down",
    depth: Annotated[int, Query(ge=1, le=32)] = 3,
) -> dict[str, Any]:
    return await reg.traverse(caller, slug, direction, depth)


class RoleBody(BaseModel):
    role: Literal["owner", "editor", "viewer"] = Field(description=f"one of {', '.join(ROLES)}")


@router.get("/twins/{slug}/roles", summary="Who has which role on a twin")
async def list_roles(slug: str, caller: Caller, reg: Registry) -> dict[str, Any]:
    twin, role = await reg.require_twin(caller, slug)
    if not has_role(caller, role, "viewer"):
        raise ForbiddenError(f"seeing the roles of {slug!r} needs a role on it")
    return {
        "roles": [{"username": u, "role": r} for _, u, r in await reg.store.list_roles(twin.id)]
    }


@router.put("/twins/{slug}/roles/{username}", summary="Grant a role (owners only)")
async def grant_role(
    slug: str, username: str, body: RoleBody, caller: Caller, reg: Registry
) -> dict[str, Any]:
    await reg.set_role(caller, slug, username, body.role)
    return {"username": username, "role": body.role}


@router.delete("/twins/{slug}/roles/{username}", summary="Take a role away (owners only)")
async def revoke_role(slug: str, username: str, caller: Caller, reg: Registry) -> dict[str, Any]:
    await reg.set_role(caller, slug, username, None)
    return {"username": username, "role": None}
