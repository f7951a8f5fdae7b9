"""Canonical twin URLs (`/twins/{slug}`) serving YAML, JSON or HTML by Accept, and `/`."""

from __future__ import annotations

from fastapi import APIRouter, Request
from starlette.responses import HTMLResponse, Response

from twinlink.api.deps import MaybeCaller, Registry
from twinlink.api.models.problem import problems
from twinlink.domain.yamlsource import dump_yaml
from twinlink.web.render import index_page, twin_page

YAML = "application/yaml"
# The document is an object in YAML as in JSON; HTML is a page about it.
_TEXT = {"schema": {"type": "string"}}
_DOCUMENT = {"schema": {"type": "object", "additionalProperties": True}}
# A token is optional here (public documents need none), but one that is sent must be valid.
router = APIRouter(
    tags=["documents"], default_response_class=Response, responses=problems(401, 404, 503)
)
_YAML_TYPES = ("application/yaml", "application/x-yaml", "text/yaml", "text/x-yaml")


def _negotiate(accept: str) -> str:
    """Pick yaml, json or html; the first acceptable in the client's order, YAML by default."""
    ranked = []
    for i, item in enumerate(accept.split(",")):
        kind, _, params = item.strip().partition(";")
        q = 1.0
        for p in params.split(";"):
            name, _, value = p.strip().partition("=")
            if name == "q":
                try:
                    q = float(value)
                except ValueError:
                    q = 0.0
        ranked.append((-q, i, kind.strip().lower()))
    for negative_q, _, kind in sorted(ranked):
        if negative_q >= 0:
            break  # q=0 means "not acceptable"
        if kind in _YAML_TYPES:
            return "yaml"
        if kind == "application/json":
            return "json"
        if kind in ("text/html", "application/xhtml+xml"):
            return "html"
        if kind in ("*/*", "application/*", "text/*"):
            return "yaml"
    return "yaml"


async def _serve(slug: str, fmt: str, caller: MaybeCaller, reg: Registry) -> Response:
    twin, _, doc = await reg.document(caller, slug)
    headers = {
        "Vary": "Accept, Authorization",
        "Link": f'<{reg.canonical_url(twin.slug)}>; rel="canonical"',
    }
    if caller.user is not None or twin.visibility != "public":
        headers["Cache-Control"] = "private, no-store"
    if fmt == "json":
        import orjson
        from starlette.responses import Response as Raw

        return Raw(orjson.dumps(doc), media_type="application/json", headers=headers)
    if fmt == "html":
        return HTMLResponse(twin_page(doc, twin.slug), headers=headers)
    return Response(dump_yaml(doc), media_type=YAML + "; charset=utf-8", headers=headers)


@router.get(
    "/twins/{slug}",
    summary="The twin's DT document (YAML, JSON or HTML by Accept)",
    responses={
        200: {"content": {YAML: _DOCUMENT, "application/json": _DOCUMENT, "text/html": _TEXT}}
    },
)
async def twin_document(
    slug: str, request: Request, caller: MaybeCaller, reg: Registry
) -> Response:
    return await _serve(slug, _negotiate(request.headers.get("accept", "")), caller, reg)


@router.get(
    "/twins/{slug}/index.yaml",
    summary="The twin's DT document as YAML",
    responses={200: {"content": {YAML: _DOCUMENT}}},
)
async def twin_yaml(slug: str, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve(slug, "yaml", caller, reg)


@router.get(
    "/twins/{slug}/index.json",
    summary="The twin's DT document as JSON",
    responses={200: {"content": {"application/json": _DOCUMENT}}},
)
async def twin_json(slug: str, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve(slug, "json", caller, reg)


@router.get("/", include_in_schema=False)
async def index(caller: MaybeCaller, reg: Registry) -> HTMLResponse:
    twins = await reg.store.list_twins(caller.visibility, limit=500)
    items = [{"slug": t.slug, "name": t.name, "id": t.dt_id} for t in twins]
    return HTMLResponse(index_page(items, caller.user is not None))
