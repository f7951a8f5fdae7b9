"""The library's listings and changes besides pushes: assets listed, described, deleted;
versions listed and deleted; tags set and removed. A mixin of LibraryService (service.py),
which holds the store, the rights and the blob sweep these use."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterable
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.domain.errors import ConflictError, InvalidInputError, NotFoundError
from twinlink.domain.library import (
    LATEST,
    AssetRecord,
    VersionRecord,
    check_kind,
    check_name,
    check_ref,
    check_scope,
    check_tag,
)
from twinlink.library.blobs import BlobStore
from twinlink.library.contents import fields_of
from twinlink.library.rights import LibraryRights
from twinlink.store.library import LibraryStore

MAX_PAGE = 1000


class LibraryChanges:
    store: LibraryStore
    rights: LibraryRights
    blobs: BlobStore
    _blob_lock: asyncio.Lock

    async def get_asset(
        self, principal: Principal, scope: str, kind: str, name: str
    ) -> AssetRecord:
        scope = check_scope(scope, principal.user.username if principal.user else None)
        what = f"{scope}/{check_kind(kind)}/{check_name(name)}"
        self.rights.check_read(principal, scope, what)
        asset = await self.store.get_asset(scope, kind, name)
        if asset is None:
            raise NotFoundError(f"the library has no {what}")
        return asset

    async def version_of(self, asset: AssetRecord, ref: str) -> VersionRecord:
        """The version of `asset` that `ref` (a tag, a digest or a digest prefix) names."""
        check_ref(ref)
        digest = asset.tags.get(ref)
        if digest is None and ref.startswith("sha256:"):
            found = await self.store.find_digests(asset.id, ref)
            if len(found) > 1:
                raise InvalidInputError(
                    f"{ref} is the start of several versions of {asset.ref} "
                    f"({', '.join(d[:19] for d in found)}...): give more of the digest"
                )
            digest = found[0] if found else None
        version = await self.store.get_version(asset.id, digest) if digest else None
        if version is None:
            tags = ", ".join(sorted(asset.tags)) or "none"
            raise NotFoundError(f"{asset.ref} has no version {ref} (its tags: {tags})")
        return version

    async def sweep(self, sha256s: Iterable[str]) -> int:
        """Delete those blobs no version lists any more; returns how many."""
        wanted = set(sha256s)
        async with self._blob_lock, self.store.blob_lock():
            unused = wanted - await self.store.referenced_blobs(wanted)
            for sha256 in unused:
                await self.blobs.delete(sha256)
        return len(unused)

    async def list_assets(
        self,
        principal: Principal,
        *,
        kind: str | None = None,
        scope: str | None = None,
        text: str | None = None,
        limit: int = 100,
        after: str | None = None,
    ) -> list[AssetRecord]:
        """The assets the caller may read, by (scope, kind, name), after the asset `after`
        (its `scope/kind/name`)."""
        scopes = self.rights.readable_scopes(principal)
        if scope is not None:
            wanted = check_scope(scope, principal.user.username if principal.user else None)
            scopes = [wanted] if scopes is None or wanted in scopes else []
        if not 1 <= limit <= MAX_PAGE:
            raise InvalidInputError(f"limit must be 1 to {MAX_PAGE}")
        return await self.store.list_assets(
            scopes,
            kind=check_kind(kind) if kind else None,
            text=text or None,
            limit=limit,
            after=_after(after) if after else None,
        )

    async def search_assets(
        self,
        principal: Principal,
        terms: list[str],
        *,
        keyword: str | None = None,
        limit: int,
        offset: int = 0,
    ) -> tuple[list[AssetRecord], int]:
        """The assets the caller may read that hold every term (the platform's search), one
        page of them, and how many there are."""
        scopes = self.rights.readable_scopes(principal)
        if scopes == []:
            return [], 0
        return await self.store.search_assets(
            scopes, terms, keyword=keyword, limit=limit, offset=offset
        )

    async def list_versions(self, asset: AssetRecord) -> list[VersionRecord]:
        return await self.store.list_versions(asset.id)

    async def update_asset(
        self, principal: Principal, scope: str, kind: str, name: str, changes: dict[str, Any]
    ) -> AssetRecord:
        asset = await self._writable(principal, scope, kind, name)
        fields = fields_of(changes, "the change")
        updated = await self.store.update_asset(asset.id, fields, time.time_ns())
        if updated is None:
            raise NotFoundError(f"the library has no {asset.ref}")
        return updated

    async def delete_asset(self, principal: Principal, scope: str, kind: str, name: str) -> None:
        asset = await self._writable(principal, scope, kind, name)
        versions = await self.store.list_versions(asset.id)
        holders = await self.store.delete_asset(asset.id)
        if holders:
            raise ConflictError(f"{asset.ref} is in use by {', '.join(holders)}: not deleted")
        await self.sweep(f.sha256 for v in versions for f in v.files)

    async def delete_version(
        self, principal: Principal, scope: str, kind: str, name: str, ref: str
    ) -> None:
        """Delete one version; `latest` moves to the newest version left if it was on it."""
        asset = await self._writable(principal, scope, kind, name)
        version = await self.version_of(asset, ref)
        holders = await self.store.delete_version(asset.id, version.digest)
        if holders:
            raise ConflictError(
                f"{asset.ref}@{version.digest[:19]} is in use by {', '.join(holders)}: not deleted"
            )
        if asset.tags.get(LATEST) == version.digest:
            left = await self.store.list_versions(asset.id)
            if left:
                await self.store.set_tag(asset.id, LATEST, left[0].digest, time.time_ns())
        await self.sweep(f.sha256 for f in version.files)

    async def set_tag(
        self, principal: Principal, scope: str, kind: str, name: str, tag: str, ref: str
    ) -> AssetRecord:
        asset = await self._writable(principal, scope, kind, name)
        version = await self.version_of(asset, ref)
        await self.store.set_tag(asset.id, check_tag(tag), version.digest, time.time_ns())
        return await self.get_asset(principal, asset.scope, kind, name)

    async def delete_tag(
        self, principal: Principal, scope: str, kind: str, name: str, tag: str
    ) -> None:
        asset = await self._writable(principal, scope, kind, name)
        if not await self.store.delete_tag(asset.id, check_tag(tag)):
            raise NotFoundError(f"{asset.ref} has no tag {tag!r}")

    async def _writable(
        self, principal: Principal, scope: str, kind: str, name: str
    ) -> AssetRecord:
        asset = await self.get_asset(principal, scope, kind, name)
        self.rights.check_write(principal, asset.scope, asset.ref)
        return asset


def _after(text: str) -> tuple[str, str, str]:
    parts = text.split("/")
    if len(parts) != 3:
        raise InvalidInputError(f"after={text!r}: give the last asset's <scope>/<kind>/<name>")
    scope, kind, name = parts
    return check_scope(scope), check_kind(kind), check_name(name)
