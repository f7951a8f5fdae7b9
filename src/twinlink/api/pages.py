"""Canonical twin URLs (`/twins/{slug}`) serving YAML, JSON or HTML by Accept, Twinbase's layout
(`/twins/{slug}/index.yaml|json|html`, the root `/index.yaml|json`), and `/`.

Every document answer carries a strong ETag (a digest of its body) and answers a matching
`If-None-Match` with 304; HEAD answers as GET without the body.
"""

from __future__ import annotations

import asyncio
import hashlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any

import orjson
from fastapi import APIRouter, Query, Request
from starlette.responses import HTMLResponse, RedirectResponse, Response

from twinlink.api.deps import MaybeCaller, Registry
from twinlink.api.federation import remote_relations
from twinlink.api.models.problem import problems
from twinlink.api.twinbase import site_index, visible_twins
from twinlink.domain.errors import InvalidInputError, NotFoundError
from twinlink.domain.records import TwinRecord
from twinlink.domain.yamlsource import dump_yaml
from twinlink.formats import FORMATS as EXPORTS
from twinlink.web.render import index_page, twin_page

YAML = "application/yaml"
# The document is an object in YAML as in JSON; HTML is a page about it.
_TEXT = {"schema": {"type": "string"}}
_DOCUMENT = {"schema": {"type": "object", "additionalProperties": True}}
_NOT_MODIFIED: dict[int | str, dict[str, Any]] = {
    304: {"description": "Not Modified: the ETag in If-None-Match is current"}
}
_MOVED: dict[int | str, dict[str, Any]] = {
    **_NOT_MODIFIED,
    308: {"description": "Permanent Redirect: the twin whose id is this URL has a new slug"},
}
# A token is optional here (public documents need none), but one that is sent must be valid.
router = APIRouter(
    tags=["documents"], default_response_class=Response, responses=problems(401, 404, 503)
)
# `?format=` wins over Accept: yaml, json, html, or an export api/exports.py registers.
FormatQuery = Annotated[
    str | None,
    Query(
        alias="format",
        description="The format, whatever Accept asks: yaml, json, html, or the document "
        "converted: wot-td (a W3C WoT Thing Description 1.1), dtdl (a DTDL v3 Interface), "
        "aas-json (an Asset Administration Shell environment).",
    ),
]
_YAML_TYPES = ("application/yaml", "application/x-yaml", "text/yaml", "text/x-yaml")


@dataclass(frozen=True, slots=True)
class Format:
    """A form a twin's document is served in: its media type, and its body made from the
    document the caller may see, the twin's slug and the request (for settings and URLs)."""

    media_type: str
    render: Callable[[dict[str, Any], str, Request], bytes]


FORMATS: dict[str, Format] = {
    "yaml": Format(YAML + "; charset=utf-8", lambda doc, _s, _r: dump_yaml(doc).encode()),
    "json": Format("application/json", lambda doc, _s, _r: orjson.dumps(doc)),
    "html": Format(
        "text/html; charset=utf-8",
        lambda doc, s, r: twin_page(doc, s, getattr(r.state, "remotes", None)).encode(),
    ),
}


def register_format(name: str, fmt: Format) -> None:
    """Let `_serve` answer in another format (api/exports.py registers the exchange formats:
    a `?format=` on /twins/{slug} names one). The built-in three cannot be replaced."""
    if name in ("yaml", "json", "html"):
        raise ValueError(f"the format {name!r} is built in")
    FORMATS[name] = fmt


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


def _etag_matches(header: str | None, etag: str) -> bool:
    """Whether If-None-Match names `etag`, by the weak comparison RFC 9110 asks for there."""
    if header is None:
        return False
    tags = [t.strip() for t in header.split(",")]
    return "*" in tags or etag in (t.removeprefix("W/") for t in tags)


def answer(request: Request, body: bytes, media_type: str, headers: dict[str, str]) -> Response:
    """`body` with its ETag, or 304 (same headers, no body) when the client holds it already.
    A HEAD request gets the GET answer's headers; the server sends no body with them."""
    etag = '"' + hashlib.blake2b(body, digest_size=16).hexdigest() + '"'
    headers = {**headers, "ETag": etag}
    if _etag_matches(request.headers.get("if-none-match"), etag):
        return Response(status_code=304, headers=headers)
    return Response(body, media_type=media_type, headers=headers)


async def _moved(slug: str, caller: MaybeCaller, reg: Registry) -> TwinRecord | None:
    """The twin whose id is this slug's canonical URL, when that twin has been
    renamed since and the caller may see it. Such an id was given to a twin created without
    one; it is meant to stay a permanent link (a dt-id), so it keeps leading to the twin."""
    dt_id = reg.canonical_url(slug)
    found = (await reg.store.get_twins_by_dt_ids([dt_id])).get(dt_id)
    if found is None or found.slug == slug:
        return None
    try:
        await reg.require_twin(caller, found.slug)  # one the caller may not see stays unknown
    except NotFoundError:
        return None
    return found


def _cache_headers(public: bool) -> dict[str, str]:
    """A public answer to a reader without a token may be kept by any cache, which asks again
    (with the ETag) before each use: documents change without notice. Anything a token
    showed stays out of caches."""
    return {
        "Vary": "Accept, Authorization",
        "Cache-Control": "no-cache" if public else "private, no-store",
    }


async def _serve(
    slug: str, fmt: str, caller: MaybeCaller, reg: Registry, request: Request
) -> Response:
    """The twin's document in `fmt` (a key of FORMATS), as the caller may see it; a twin
    renamed since its id was made from its canonical URL is redirected to."""
    try:
        twin, _, doc = await reg.document(caller, slug)
    except NotFoundError:
        moved = await _moved(slug, caller, reg)
        if moved is None:
            raise
        # The rest of the path (`/index.json`) and the query follow the twin to its new slug.
        rest = request.url.path.removeprefix(f"/twins/{slug}")
        query = f"?{request.url.query}" if request.url.query else ""
        target = reg.canonical_url(moved.slug) + rest + query
        # A 308 may be cached: one a token was shown must not reach other readers.
        headers = _cache_headers(caller.user is None and moved.visibility == "public")
        return RedirectResponse(target, status_code=308, headers=headers)
    if fmt == "html":  # the twins of other instances it names, linked (docs/federation.md)
        request.state.remotes = await remote_relations(request, doc)
    form = FORMATS[fmt]
    headers = _cache_headers(caller.user is None and twin.visibility == "public")
    headers["Link"] = f'<{reg.canonical_url(twin.slug)}>; rel="canonical"'
    if fmt in ("yaml", "json", "html"):
        body = form.render(doc, twin.slug, request)
    else:  # an export (api/exports.py), the AAS SDK's objects above all: off the event loop
        body = await asyncio.to_thread(form.render, doc, twin.slug, request)
    return answer(request, body, form.media_type, headers)


_ANY_FORMAT = {YAML: _DOCUMENT, "application/json": _DOCUMENT, "text/html": _TEXT}
_ANY_FORMAT.update({media_type: _DOCUMENT for media_type, _ in EXPORTS.values()})


@router.get(
    "/twins/{slug}",
    summary="The twin's DT document (YAML, JSON or HTML by Accept), or ?format= an export",
    responses={200: {"content": _ANY_FORMAT}, **_MOVED},
)
@router.head("/twins/{slug}", include_in_schema=False)
async def twin_document(
    slug: str, request: Request, caller: MaybeCaller, reg: Registry, fmt: FormatQuery = None
) -> Response:
    if fmt is None:
        fmt = _negotiate(request.headers.get("accept", ""))
    elif fmt not in FORMATS:
        names = ", ".join(repr(name) for name in FORMATS)
        raise InvalidInputError(f"there is no format {fmt!r} here; use one of {names}")
    return await _serve(slug, fmt, caller, reg, request)


@router.get(
    "/twins/{slug}/index.yaml",
    summary="The twin's DT document as YAML (Twinbase's layout)",
    responses={200: {"content": {YAML: _DOCUMENT}}, **_MOVED},
)
@router.head("/twins/{slug}/index.yaml", include_in_schema=False)
async def twin_yaml(slug: str, request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve(slug, "yaml", caller, reg, request)


@router.get(
    "/twins/{slug}/index.json",
    summary="The twin's DT document as JSON (Twinbase's layout)",
    responses={200: {"content": {"application/json": _DOCUMENT}}, **_MOVED},
)
@router.head("/twins/{slug}/index.json", include_in_schema=False)
async def twin_json(slug: str, request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve(slug, "json", caller, reg, request)


@router.get(
    "/twins/{slug}/index.html",
    summary="The twin's page (Twinbase's layout)",
    responses={200: {"content": {"text/html": _TEXT}}, **_MOVED},
)
@router.head("/twins/{slug}/index.html", include_in_schema=False)
async def twin_html(slug: str, request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve(slug, "html", caller, reg, request)


async def _serve_index(fmt: str, caller: MaybeCaller, reg: Registry, request: Request) -> Response:
    """The root index in Twinbase's shape, listing the twins the caller may see."""
    owner: str = request.app.state.settings.site_owner
    index = site_index(reg, owner, await visible_twins(reg, caller))
    if fmt == "json":
        body, media_type = orjson.dumps(index), "application/json"
    else:
        body, media_type = dump_yaml(index).encode(), YAML + "; charset=utf-8"
    return answer(request, body, media_type, _cache_headers(caller.user is None))


_TWIN_ENTRY = {
    "type": "object",
    "required": ["url", "name"],
    "properties": {"url": {"type": "string"}, "name": {"type": "string"}},
}
_INDEX = {
    "schema": {
        "type": "object",
        "required": ["baseurl", "owner", "twins"],
        "properties": {
            "baseurl": {"type": "string"},
            "owner": {"type": "object", "additionalProperties": True},
            "twins": {"type": "array", "items": _TWIN_ENTRY},
        },
    }
}


@router.get(
    "/index.yaml",
    summary="The site's twins in Twinbase's index shape (baseurl, owner, twins), as YAML",
    responses={200: {"content": {YAML: _INDEX}}, **_NOT_MODIFIED},
)
@router.head("/index.yaml", include_in_schema=False)
async def site_yaml(request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve_index("yaml", caller, reg, request)


@router.get(
    "/index.json",
    summary="The site's twins in Twinbase's index shape (baseurl, owner, twins), as JSON",
    responses={200: {"content": {"application/json": _INDEX}}, **_NOT_MODIFIED},
)
@router.head("/index.json", include_in_schema=False)
async def site_json(request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    return await _serve_index("json", caller, reg, request)


@router.get("/", include_in_schema=False)
@router.get("/index.html", include_in_schema=False)
async def index(caller: MaybeCaller, reg: Registry) -> HTMLResponse:
    twins = await reg.store.list_twins(caller.visibility, limit=500)
    items = [{"slug": t.slug, "name": t.name, "id": t.dt_id} for t in twins]
    return HTMLResponse(index_page(items, caller.user is not None))
