"""The interface of the library's tables: assets, their versions, tags and holds.

Files are not here: a version lists its files by sha256 and the blob store keeps them
(`twinlink.library.blobs`). Each method that changes several rows does so in one
transaction, so a push lands whole (asset, version and tags) or not at all.
"""

from __future__ import annotations

from collections.abc import Iterable
from contextlib import AbstractAsyncContextManager
from dataclasses import asdict, dataclass
from typing import Any, Protocol

import orjson

from twinlink.domain.library import AssetRecord, FileEntry, VersionRecord
from twinlink.store.rows import Row


@dataclass(frozen=True, slots=True)
class AssetFields:
    """The describing fields of an asset; None leaves a field as it is."""

    description: str | None = None
    keywords: list[str] | None = None
    licence: str | None = None
    author: str | None = None

    def as_dict(self) -> dict[str, Any]:
        return {k: v for k, v in asdict(self).items() if v is not None}


class LibraryStore(Protocol):
    async def get_asset(self, scope: str, kind: str, name: str) -> AssetRecord | None:
        """The asset with its tags and version count, or None."""
        ...

    async def list_assets(
        self,
        scopes: list[str] | None,
        *,
        kind: str | None,
        text: str | None,
        limit: int,
        after: tuple[str, str, str] | None,
    ) -> list[AssetRecord]:
        """Assets in `scopes` (None: every scope), ordered by (scope, kind, name), after the
        key `after`; `text` matches names, descriptions and keywords (case-insensitive)."""
        ...

    async def search_assets(
        self,
        scopes: list[str] | None,
        terms: list[str],
        *,
        keyword: str | None,
        limit: int,
        offset: int,
    ) -> tuple[list[AssetRecord], int]:
        """A page of the assets in `scopes` (None: all) whose name, description or keywords
        hold every term (lower-case), those with every term in the name first, then by
        (scope, kind, name); with `keyword`, only assets that have it. And how many match."""
        ...

    async def put_version(
        self,
        scope: str,
        kind: str,
        name: str,
        version: VersionRecord,
        tags: Iterable[str],
        fields: AssetFields,
        now_ns: int,
    ) -> tuple[AssetRecord, VersionRecord, bool]:
        """Create the asset if it is new, add the version unless the asset has one of the
        same digest (then the stored one is returned, and False), point `tags` at it, and
        set the fields given. `version.asset_id` is ignored."""
        ...

    async def update_asset(
        self, asset_id: int, fields: AssetFields, now_ns: int
    ) -> AssetRecord | None: ...

    async def delete_asset(self, asset_id: int) -> list[str] | None:
        """Delete the asset with its versions and tags; None if it was deleted, else the
        holders that keep one of its versions (nothing deleted then)."""
        ...

    async def list_versions(self, asset_id: int) -> list[VersionRecord]:
        """The asset's versions, newest first."""
        ...

    async def get_version(self, asset_id: int, digest: str) -> VersionRecord | None: ...

    async def find_digests(self, asset_id: int, prefix: str) -> list[str]:
        """The asset's version digests that start with `prefix` (at most a few)."""
        ...

    async def delete_version(self, asset_id: int, digest: str) -> list[str] | None:
        """Delete the version and the tags on it; None if done, else its holders."""
        ...

    async def set_tag(self, asset_id: int, tag: str, digest: str, now_ns: int) -> None: ...

    async def delete_tag(self, asset_id: int, tag: str) -> bool: ...

    async def add_holds(self, holder: str, versions: Iterable[tuple[int, str]]) -> None:
        """Hold each (asset id, digest) for `holder`; holding twice is no error."""
        ...

    async def release_holds(self, holder: str) -> int: ...

    async def list_holders(self, asset_id: int, digest: str | None = None) -> list[str]:
        """Who holds the version (or any version of the asset when `digest` is None)."""
        ...

    async def referenced_blobs(self, sha256s: Iterable[str]) -> set[str]:
        """Those of `sha256s` that some version of some asset still lists."""
        ...

    def blob_lock(self) -> AbstractAsyncContextManager[None]:
        """Held while blobs are swept and while a push checks its blobs and adds its version,
        by every node that shares the store (one process alone: nothing to hold)."""
        ...


# Rows of both backends read as records (rows.py's way: by column name, no driver needed).
ASSET_COLUMNS = (
    "id, scope, kind, name, description, keywords, licence, author, created_by, created_ns,"
    " updated_ns"
)
VERSION_COLUMNS = "asset_id, digest, files, size, meta, created_by, created_ns"


def asset_of(row: Row) -> AssetRecord:
    return AssetRecord(
        id=row["id"],
        scope=row["scope"],
        kind=row["kind"],
        name=row["name"],
        description=row["description"],
        keywords=_json(row["keywords"]),
        licence=row["licence"],
        author=row["author"],
        created_by=row["created_by"],
        created_ns=row["created_ns"],
        updated_ns=row["updated_ns"],
    )


def version_of(row: Row) -> VersionRecord:
    return VersionRecord(
        asset_id=row["asset_id"],
        digest=row["digest"],
        files=[FileEntry(**f) for f in _json(row["files"])],
        size=row["size"],
        meta=_json(row["meta"]),
        created_by=row["created_by"],
        created_ns=row["created_ns"],
    )


def files_json(files: list[FileEntry]) -> str:
    return orjson.dumps([f.as_dict() for f in files]).decode()


def _json(value: Any) -> Any:
    # SQLite gives the text back; asyncpg gives jsonb as text too unless a codec is set.
    return orjson.loads(value) if isinstance(value, (str, bytes)) else value
