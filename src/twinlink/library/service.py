"""The library service: resolve references, push versions, hold what is in use.

Processors, deployments and the API come here; rights are checked here (library/rights.py),
files go through the blob store, rows through the store. A push unpacks into blobs first and
then writes the version's rows in one transaction; a blob no version lists any more (after a
delete, or a push refused after unpacking) is swept under the same lock that a push's final
step takes (the process's, and the store's for the nodes that share it), so a sweep never
removes a blob a push is about to list.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import AsyncIterator, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

from twinlink.auth.rights import Principal
from twinlink.config import Settings
from twinlink.domain.errors import ConflictError, InvalidInputError, NotFoundError
from twinlink.domain.library import (
    LATEST,
    AssetRecord,
    FileEntry,
    VersionRecord,
    check_kind,
    check_name,
    check_scope,
    check_tag,
    parse_ref,
)
from twinlink.library import archive
from twinlink.library.blobs import BlobStore, FileBlobStore
from twinlink.library.changes import LibraryChanges
from twinlink.library.contents import (
    FmuInspector,
    fields_of,
    fmu_paths,
    inspect_fmus,
    merged,
    read_asset_yaml,
)
from twinlink.library.rights import LibraryRights
from twinlink.store.library import LibraryStore

_FIELD_KEYS = ("description", "keywords", "licence", "author")


@dataclass(frozen=True, slots=True)
class Resolved:
    asset: AssetRecord
    version: VersionRecord
    path: str | None  # the #path asked for (or the only file), None for the whole tree

    @property
    def pinned(self) -> str:
        a = self.asset
        text = f"lib:{a.scope}/{a.kind}/{a.name}@{self.version.digest}"
        return text + (f"#{self.path}" if self.path else "")


@dataclass(frozen=True, slots=True)
class PushResult:
    asset: AssetRecord
    version: VersionRecord
    created: bool


class LibraryService(LibraryChanges):
    @classmethod
    def configured(
        cls, settings: Settings, store: LibraryStore, fmu_inspector: FmuInspector
    ) -> LibraryService:
        """As the server's settings have it: blobs in data_dir/library/blobs, its limits and
        rights. FMUs pushed are checked as twins' uploads are: the library does not import
        the processors, it is handed their check (`fmu_inspector`)."""
        rights = LibraryRights(settings.library_curators, settings.fmu_uploaders)
        blobs = FileBlobStore(settings.data_dir / "library" / "blobs")
        blobs.remove_stale_temps()  # left by pushes a crash cut off (a day old at least)
        return cls(store, blobs, settings.library_max_mb * 2**20, rights, fmu_inspector)

    def __init__(
        self,
        store: LibraryStore,
        blobs: BlobStore,
        max_bytes: int,
        rights: LibraryRights | None = None,
        fmu_inspector: FmuInspector | None = None,
    ) -> None:
        self.store = store
        self.blobs = blobs
        self.limits = archive.Limits(max_bytes=max_bytes)
        self.rights = rights or LibraryRights()
        self.fmu_inspector = fmu_inspector
        self._blob_lock = asyncio.Lock()

    # -- reading --------------------------------------------------------------------------

    async def resolve(self, principal: Principal, ref: str, *, kind: str | None = None) -> Resolved:
        """The version `ref` names, with read rights checked. Without a scope the asset is
        looked for in the caller's own space, then their groups (sorted), then common."""
        parsed = parse_ref(ref)
        if kind is not None and parsed.kind not in (None, kind):
            raise InvalidInputError(f"{ref!r} names a {parsed.kind} asset; {kind} is wanted here")
        wanted = parsed.kind or kind
        if wanted is None:
            raise InvalidInputError(f"{ref!r} does not say the kind: write <kind>/{parsed.name}")
        check_kind(wanted)
        if parsed.scope is not None:
            asset = await self.get_asset(principal, parsed.scope, wanted, parsed.name)
        else:
            asset = await self._first_in_lookup(principal, wanted, parsed.name)
        version = await self.version_of(asset, parsed.ref or LATEST)
        return Resolved(asset, version, _path_in(version, parsed.path))

    async def _first_in_lookup(self, principal: Principal, kind: str, name: str) -> AssetRecord:
        order = self.rights.lookup_order(principal)
        for scope in order:
            asset = await self.store.get_asset(scope, kind, name)
            if asset is not None:
                return asset
        where = ", ".join(order) or "any scope (sign in to read the library)"
        raise NotFoundError(f"the library has no {kind}/{name} in {where}")

    async def file_path(self, resolved: Resolved) -> Path:
        """The local path of the file `resolved` names (its #path or its only file)."""
        if resolved.path is None:
            names = ", ".join(f.path for f in resolved.version.files[:20])
            raise InvalidInputError(
                f"{resolved.pinned} has several files ({names}): name one with #<path>"
            )
        return await self.blobs.local_path(_entry(resolved.version, resolved.path).sha256)

    async def materialize(self, resolved: Resolved, dest: Path) -> None:
        """Write the version's whole tree under `dest`."""
        await archive.materialize(resolved.version.files, self.blobs, dest)

    async def read_text(self, resolved: Resolved, path: str, max_bytes: int = 1 << 20) -> str:
        entry = _entry(resolved.version, path)
        if entry.size > max_bytes:
            raise InvalidInputError(f"{path} of {resolved.pinned} is over {max_bytes} bytes")
        data = b"".join([chunk async for chunk in self.blobs.read(entry.sha256)])
        try:
            return data.decode("utf-8")
        except UnicodeDecodeError as err:
            raise InvalidInputError(f"{path} of {resolved.pinned} is not UTF-8 text") from err

    def file_bytes(
        self, version: VersionRecord, path: str
    ) -> tuple[FileEntry, AsyncIterator[bytes]]:
        entry = _entry(version, path)
        return entry, self.blobs.read(entry.sha256)

    # -- holds ----------------------------------------------------------------------------

    async def hold(self, holder: str, resolved: Iterable[Resolved]) -> None:
        await self.store.add_holds(holder, [(r.asset.id, r.version.digest) for r in resolved])

    async def release(self, holder: str) -> None:
        await self.store.release_holds(holder)

    # -- pushing --------------------------------------------------------------------------

    async def push(
        self,
        principal: Principal,
        scope: str,
        kind: str,
        name: str,
        body: AsyncIterator[bytes],
        fmt: str,
        *,
        filename: str | None = None,
        tags: Iterable[str] = (LATEST,),
        meta: dict[str, Any] | None = None,
    ) -> PushResult:
        scope = self._scope(principal, scope)
        what = f"{scope}/{check_kind(kind)}/{check_name(name)}"
        tags = [check_tag(t) for t in dict.fromkeys(tags)]
        self.rights.check_write(principal, scope, what)
        if fmt == "file" and filename:  # refused before the upload, not after it
            self.rights.check_fmu_upload(principal, fmu_paths([FileEntry(filename, "", 0)]))
        meta = dict(meta or {})
        fields = fields_of({k: meta.pop(k) for k in _FIELD_KEYS if k in meta}, "meta")
        files = await archive.receive(body, _format(fmt), self.blobs, self.limits, filename)
        try:
            if not files:
                raise InvalidInputError("the upload holds no files: push a file or a folder")
            self.rights.check_fmu_upload(principal, fmu_paths(files))
            fmus = await inspect_fmus(files, self.blobs, self.fmu_inspector)
            fields = merged(await read_asset_yaml(files, self.blobs), fields)
            version = VersionRecord(
                asset_id=0,
                digest=archive.version_digest(files),
                files=sorted(files, key=lambda f: f.path),
                size=sum(f.size for f in files),
                meta={**meta, "fmus": fmus} if fmus else meta,
                created_by=_username(principal),
                created_ns=time.time_ns(),
            )
            async with self._blob_lock, self.store.blob_lock():
                await self._check_blobs(files)
                asset, stored, created = await self.store.put_version(
                    scope, kind, name, version, tags, fields, version.created_ns
                )
        except BaseException:
            await self.sweep(f.sha256 for f in files)
            raise
        return PushResult(asset, stored, created)

    async def _check_blobs(self, files: list[FileEntry]) -> None:
        for f in files:
            if not await self.blobs.exists(f.sha256):  # swept by a delete meanwhile
                raise ConflictError("the library changed during the push; push again")

    def _scope(self, principal: Principal, scope: str) -> str:
        return check_scope(scope, _username(principal))


def _format(fmt: str) -> archive.Format:
    if fmt not in archive.FORMATS:
        raise InvalidInputError(f"{fmt!r} is not an upload format: use one of tar, tgz, zip, file")
    return cast("archive.Format", fmt)


def _username(principal: Principal) -> str | None:
    return principal.user.username if principal.user else None


def _path_in(version: VersionRecord, path: str | None) -> str | None:
    if path is not None:
        return _entry(version, path).path
    return version.files[0].path if len(version.files) == 1 else None


def _entry(version: VersionRecord, path: str) -> FileEntry:
    for entry in version.files:
        if entry.path == path:
            return entry
    names = ", ".join(f.path for f in version.files[:20])
    raise NotFoundError(f"the version {version.digest[:19]} has no file {path!r} (it has: {names})")
