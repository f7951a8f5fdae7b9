"""/api/v1/twins: the twin registry."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request, Response
from pydantic import BaseModel, Field

from twinlink.api._body import DOCUMENT_BODY, read_documents
from twinlink.api.deps import Caller, Registry
from twinlink.api.models.problem import problems
from twinlink.api.models.twins import (
    Applied,
    AppliedList,
    DeletedTwins,
    Parts,
    RelationNode,
    RoleChange,
    RoleGrant,
    Roles,
    Twin,
    TwinPage,
    TwinSummary,
    Updated,
)
from twinlink.api.responses import JSONAnswer
from twinlink.auth.rights import has_role, may_see_level
from twinlink.domain.errors import ForbiddenError
from twinlink.domain.records import ROLES, TwinRecord
from twinlink.domain.yamlsource import dump_yaml
from twinlink.registry.build import human_time
from twinlink.registry.service import Applied as AppliedTwin
from twinlink.registry.service import RegistryService

router = APIRouter(prefix="/api/v1", tags=["twins"], responses=problems(401, 404, 422, 503))
YAML = "application/yaml"
# Routes that store documents: they are checked (422, 413 when too large) and may conflict.
STORING = problems(409, 413, 507)


def summary(
    reg: RegistryService, twin: TwinRecord, levels: list[str] | None = None
) -> dict[str, Any]:
    """The summary fields of a twin, as keyword arguments of the models built on them."""
    return {
        "slug": twin.slug,
        "id": twin.dt_id,
        "name": twin.name,
        "url": reg.canonical_url(twin.slug),
        "created": human_time(twin.created_ns),
        "modified": human_time(twin.modified_ns),
        "levels": levels if levels is not None else twin.levels,
    }


def _applied(reg: RegistryService, a: AppliedTwin) -> Applied:
    return Applied(**summary(reg, a.twin, a.levels), outcome=a.outcome)


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
) -> TwinPage:
    twins = await reg.store.list_twins(
        caller.visibility,
        limit=limit + 1,
        after_slug=cursor,
        keyword=keyword,
        name_contains=q,
        role_user_id=caller.user.id if mine and caller.user else None,
    )
    page = twins[:limit]
    return TwinPage(
        items=[TwinSummary(**summary(reg, t)) for t in page],
        next_cursor=page[-1].slug if len(twins) > limit else None,
    )


@router.post(
    "/twins",
    status_code=201,
    summary="Create a twin",
    openapi_extra=DOCUMENT_BODY,
    responses={**problems(403), **STORING},
)
async def create_twin(
    request: Request,
    caller: Caller,
    reg: Registry,
    slug: Annotated[str | None, Query(description="slug to use instead of the derived one")] = None,
) -> Applied:
    docs = await read_documents(request)
    result = await reg.apply(caller, docs, slug=slug, mode="create")
    return _applied(reg, result[0])


@router.post(
    "/apply",
    summary="Create or update twins from documents (idempotent)",
    openapi_extra=DOCUMENT_BODY,
    responses={**problems(403), **STORING},
)
async def apply(request: Request, caller: Caller, reg: Registry) -> AppliedList:
    docs = await read_documents(request)
    results = await reg.apply(caller, docs)
    return AppliedList(results=[_applied(reg, a) for a in results])


@router.get(
    "/twins/{slug}",
    summary="A twin and its document as the caller may see it",
    response_class=JSONAnswer,
    response_model=Twin,
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


@router.put(
    "/twins/{slug}",
    summary="Update a twin's document parts",
    openapi_extra=DOCUMENT_BODY,
    responses={**problems(403), **STORING},
    response_model_exclude_unset=True,  # `dry_run` only when it was one
)
async def update_twin(
    slug: str,
    request: Request,
    caller: Caller,
    reg: Registry,
    dry_run: Annotated[
        bool, Query(description="check the documents and the rights; store nothing")
    ] = False,
) -> Updated:
    docs = await read_documents(request)
    result = await reg.apply(caller, docs, slug=slug, mode="update", dry_run=dry_run)
    fields = {**summary(reg, result[0].twin, result[0].levels), "outcome": result[0].outcome}
    return Updated(**fields, dry_run=True) if dry_run else Updated(**fields)


@router.delete(
    "/twins/{slug}",
    summary="Delete a twin (and, with cascade, its descendants)",
    responses=problems(403, 409, 507),
)
async def delete_twin(
    slug: str,
    caller: Caller,
    reg: Registry,
    cascade: Annotated[bool, Query(description="also delete every descendant")] = False,
) -> DeletedTwins:
    return DeletedTwins(deleted=await reg.delete(caller, slug, cascade))


@router.get("/twins/{slug}/parts", summary="The privacy parts of a twin the caller may see")
async def list_parts(slug: str, caller: Caller, reg: Registry) -> Parts:
    twin, role = await reg.require_twin(caller, slug)
    return Parts(levels=[lv for lv in twin.levels if may_see_level(caller, role, lv)])


@router.get(
    "/twins/{slug}/parts/{level}",
    summary="One privacy part, as stored (JSON, or YAML with format=yaml)",
    response_model=dict[str, Any],
    responses={200: {"content": {YAML: {"schema": {"type": "object"}}}}, **problems(403)},
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


@router.delete(
    "/twins/{slug}/parts/{level}",
    summary="Remove one privacy part",
    responses=problems(403, 409, 507),
)
async def delete_part(slug: str, level: str, caller: Caller, reg: Registry) -> TwinSummary:
    twin = await reg.delete_part(caller, slug, level)
    return TwinSummary(**summary(reg, twin))


@router.get(
    "/twins/{slug}/relations",
    summary="Descendants (down) or ancestors (up) to a depth",
    response_class=JSONAnswer,
    response_model=RelationNode,
)
async def relations(
    request: Request,
    slug: str,
    caller: Caller,
    reg: Registry,
    direction: Literal["down", "up"] = "down",
    depth: Annotated[int, Query(ge=1, le=32)] = 3,
) -> JSONAnswer:
    tree = await reg.traverse(caller, slug, direction, depth)
    federation = request.app.state.services.federation
    if federation is not None:  # other instances' twins named by dt-id (docs/federation.md)
        await federation.resolver.decorate(tree)
    return JSONAnswer(tree)


class RoleBody(BaseModel):
    role: Literal["owner", "editor", "viewer"] = Field(description=f"one of {', '.join(ROLES)}")


@router.get("/twins/{slug}/roles", summary="Who has which role on a twin", responses=problems(403))
async def list_roles(slug: str, caller: Caller, reg: Registry) -> Roles:
    twin, role = await reg.require_twin(caller, slug)
    if not has_role(caller, role, "viewer"):
        raise ForbiddenError(f"seeing the roles of {slug!r} needs a role on it")
    rows = await reg.store.list_roles(twin.id)
    return Roles(roles=[RoleGrant(username=u, role=r) for _, u, r in rows])


@router.put(
    "/twins/{slug}/roles/{username}",
    summary="Grant a role (owners only)",
    responses=problems(403, 409, 507),
)
async def grant_role(
    slug: str, username: str, body: RoleBody, caller: Caller, reg: Registry
) -> RoleChange:
    await reg.set_role(caller, slug, username, body.role)
    return RoleChange(username=username, role=body.role)


@router.delete(
    "/twins/{slug}/roles/{username}",
    summary="Take a role away (owners only)",
    responses=problems(403, 409, 507),
)
async def revoke_role(slug: str, username: str, caller: Caller, reg: Registry) -> RoleChange:
    await reg.set_role(caller, slug, username, None)
    return RoleChange(username=username, role=None)
