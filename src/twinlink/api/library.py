"""/api/v1/library: assets, their versions (pushed and fetched as streamed archives), files
and tags (docs/library.md). Every route needs a token; rights per scope are the service's."""

from __future__ import annotations

from typing import Annotated, Any, Literal
from urllib.parse import quote

from fastapi import APIRouter, Depends, Query, Request, Response
from fastapi.responses import StreamingResponse

from twinlink.api.deps import Caller
from twinlink.api.models.library import (
    AssetChange,
    AssetDetail,
    Assets,
    AssetView,
    PushAnswer,
    TagBody,
    Versions,
    VersionView,
)
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.domain.errors import NotFoundError
from twinlink.domain.library import LATEST, AssetRecord, VersionRecord
from twinlink.library import archive
from twinlink.library.service import LibraryService

router = APIRouter(
    prefix="/api/v1/library",
    tags=["library"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
# Changing the library: the scope may be read-only to the caller (403), a version in use (409).
CHANGING = problems(403, 409, 507)
ASSET = "/{scope}/{kind}/{name}"
ArchiveFormat = Literal["tar", "tgz", "zip"]
BINARY = {"schema": {"type": "string", "format": "binary"}}
MEDIA = {"tar": "application/x-tar", "tgz": "application/gzip", "zip": "application/zip"}
SUFFIX = {"tar": "tar", "tgz": "tar.gz", "zip": "zip"}


def library_service(request: Request) -> LibraryService:
    return request.app.state.services.library  # type: ignore[no-any-return]


Library = Annotated[LibraryService, Depends(library_service)]


def asset_view(asset: AssetRecord) -> dict[str, Any]:
    return {
        "scope": asset.scope,
        "kind": asset.kind,
        "name": asset.name,
        "ref": asset.ref,
        "description": asset.description,
        "keywords": asset.keywords,
        "licence": asset.licence,
        "author": asset.author,
        "tags": asset.tags,
        "latest": asset.tags.get(LATEST),
        "versions": asset.versions,
        "created_by": asset.created_by,
        "created_ns": asset.created_ns,
        "updated_ns": asset.updated_ns,
    }


def version_view(asset: AssetRecord, version: VersionRecord, files: bool = True) -> dict[str, Any]:
    view: dict[str, Any] = {
        "digest": version.digest,
        "size": version.size,
        "file_count": len(version.files),
        "meta": version.meta,
        "tags": sorted(t for t, d in asset.tags.items() if d == version.digest),
        "created_ns": version.created_ns,
        "created_by": version.created_by,
    }
    if files:
        view["files"] = [f.as_dict() for f in version.files]
    return view


@router.get(
    "",
    summary="Assets the caller may read, by scope, kind and name",
    response_class=JSONAnswer,
    response_model=Assets,
)
async def list_assets(
    caller: Caller,
    library: Library,
    kind: str | None = None,
    scope: str | None = None,
    q: Annotated[str | None, Query(max_length=200, description="words in name, text")] = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
    after: Annotated[str | None, Query(description="the last asset's ref")] = None,
) -> JSONAnswer:
    found = await library.list_assets(
        caller, kind=kind, scope=scope, text=q, limit=limit, after=after
    )
    more = found[-1].ref if len(found) == limit else None
    return JSONAnswer({"assets": [asset_view(a) for a in found], "next": more})


@router.get(
    ASSET,
    summary="An asset with its versions, newest first",
    response_class=JSONAnswer,
    response_model=AssetDetail,
)
async def get_asset(
    scope: str, kind: str, name: str, caller: Caller, library: Library
) -> JSONAnswer:
    asset = await library.get_asset(caller, scope, kind, name)
    versions = await library.list_versions(asset)
    view = asset_view(asset)
    view["version_count"] = view["versions"]
    view["versions"] = [version_view(asset, v, files=False) for v in versions]
    return JSONAnswer(view)


@router.patch(
    ASSET,
    summary="Change an asset's description, keywords, licence or author",
    response_class=JSONAnswer,
    response_model=AssetView,
    responses=CHANGING,
)
async def update_asset(
    scope: str, kind: str, name: str, body: AssetChange, caller: Caller, library: Library
) -> JSONAnswer:
    changes = body.model_dump(exclude_unset=True)
    return JSONAnswer(asset_view(await library.update_asset(caller, scope, kind, name, changes)))


@router.delete(
    ASSET,
    summary="Delete an asset with all its versions (409 while one is in use)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_asset(
    scope: str, kind: str, name: str, caller: Caller, library: Library
) -> Response:
    await library.delete_asset(caller, scope, kind, name)
    return Response(status_code=204)


@router.post(
    ASSET + "/versions",
    summary="Push a version: the body is the archive (tar, tgz, zip) or one file, streamed; "
    "201 when new, 200 when a version with the same content existed (its tags are set)",
    response_class=JSONAnswer,
    status_code=201,
    response_model=PushAnswer,
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
async def push_version(
    scope: str,
    kind: str,
    name: str,
    request: Request,
    caller: Caller,
    library: Library,
    fmt: Annotated[str, Query(alias="format", description="tar, tgz, zip or file")] = "tar",
    filename: Annotated[str | None, Query(description="format=file: the file's name")] = None,
    tag: Annotated[list[str] | None, Query(description="tags to point at it")] = None,
    latest: Annotated[bool, Query(description="false: leave `latest` where it is")] = True,
) -> JSONAnswer:
    tags = [*(tag or []), *([LATEST] if latest else [])]
    pushed = await library.push(
        caller, scope, kind, name, request.stream(), fmt, filename=filename, tags=tags
    )
    answer = {
        "asset": asset_view(pushed.asset),
        "version": version_view(pushed.asset, pushed.version),
        "created": pushed.created,
    }
    return JSONAnswer(answer, status_code=201 if pushed.created else 200)


@router.get(
    ASSET + "/versions",
    summary="The asset's versions, newest first (without their files)",
    response_class=JSONAnswer,
    response_model=Versions,
)
async def list_versions(
    scope: str, kind: str, name: str, caller: Caller, library: Library
) -> JSONAnswer:
    asset = await library.get_asset(caller, scope, kind, name)
    versions = await library.list_versions(asset)
    return JSONAnswer({"versions": [version_view(asset, v, files=False) for v in versions]})


@router.get(
    ASSET + "/versions/{ref}",
    summary="A version (a tag, a digest or a digest prefix of 12+ hex) with its files",
    response_class=JSONAnswer,
    response_model=VersionView,
)
async def get_version(
    scope: str, kind: str, name: str, ref: str, caller: Caller, library: Library
) -> JSONAnswer:
    asset = await library.get_asset(caller, scope, kind, name)
    return JSONAnswer(version_view(asset, await library.version_of(asset, ref)))


@router.get(
    ASSET + "/versions/{ref}/archive",
    summary="A version as an archive, streamed",
    response_class=StreamingResponse,
    responses={200: {"content": dict.fromkeys(MEDIA.values(), BINARY)}},
)
async def get_archive(
    scope: str,
    kind: str,
    name: str,
    ref: str,
    caller: Caller,
    library: Library,
    fmt: Annotated[ArchiveFormat, Query(alias="format")] = "tar",
) -> StreamingResponse:
    asset = await library.get_asset(caller, scope, kind, name)
    version = await library.version_of(asset, ref)
    await _check_blobs(library, version)  # before the answer starts: an error is still a 404
    filename = f"{asset.name}-{version.digest[7:19]}.{SUFFIX[fmt]}"
    return StreamingResponse(
        archive.send(version.files, library.blobs, fmt),
        media_type=MEDIA[fmt],
        headers={"Content-Disposition": _attachment(filename)},
    )


@router.get(
    ASSET + "/versions/{ref}/files/{path:path}",
    summary="One file of a version, streamed (always as a download)",
    response_class=StreamingResponse,
    responses={200: {"content": {"application/octet-stream": BINARY}}},
)
async def get_file(
    scope: str, kind: str, name: str, ref: str, path: str, caller: Caller, library: Library
) -> StreamingResponse:
    asset = await library.get_asset(caller, scope, kind, name)
    version = await library.version_of(asset, ref)
    entry, chunks = library.file_bytes(version, path)
    await library.blobs.local_path(entry.sha256)  # missing: a 404 before the answer starts
    # Always a download and never sniffed: a pushed .html or .svg shown from the API's own
    # origin could run script with the viewer's session.
    return StreamingResponse(
        chunks,
        media_type="application/octet-stream",
        headers={
            "Content-Disposition": _attachment(entry.path.rsplit("/", 1)[-1]),
            "Content-Length": str(entry.size),
            "X-Content-Type-Options": "nosniff",
        },
    )


@router.delete(
    ASSET + "/versions/{ref}",
    summary="Delete a version (409 while a processor or deployment uses it)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_version(
    scope: str, kind: str, name: str, ref: str, caller: Caller, library: Library
) -> Response:
    await library.delete_version(caller, scope, kind, name, ref)
    return Response(status_code=204)


@router.put(
    ASSET + "/tags/{tag}",
    summary="Point a tag at a version (moved if it is set)",
    response_class=JSONAnswer,
    response_model=AssetView,
    responses=CHANGING,
)
async def set_tag(
    scope: str, kind: str, name: str, tag: str, body: TagBody, caller: Caller, library: Library
) -> JSONAnswer:
    return JSONAnswer(
        asset_view(await library.set_tag(caller, scope, kind, name, tag, body.version))
    )


@router.delete(
    ASSET + "/tags/{tag}",
    summary="Remove a tag (the version stays)",
    status_code=204,
    response_class=Response,
    responses=CHANGING,
)
async def delete_tag(
    scope: str, kind: str, name: str, tag: str, caller: Caller, library: Library
) -> Response:
    await library.delete_tag(caller, scope, kind, name, tag)
    return Response(status_code=204)


async def _check_blobs(library: LibraryService, version: VersionRecord) -> None:
    for entry in version.files:
        if not await library.blobs.exists(entry.sha256):
            raise NotFoundError(
                f"a file of version {version.digest[:19]} is missing from the library's "
                f"store ({entry.path}); push the version again"
            )


def _attachment(filename: str) -> str:
    # RFC 6266: an ASCII fallback and the exact name in UTF-8.
    fallback = "".join(c if c.isascii() and c.isprintable() and c not in '"\\' else "_"
                       for c in filename)  # fmt: skip
    return f"attachment; filename=\"{fallback}\"; filename*=UTF-8''{quote(filename)}"
