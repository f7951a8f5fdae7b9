"""The library in a workspace's folder, written at each start:

- `library/<kind>/<name>/`: the latest version of each asset of the user's own space, as
  copies the user may change. An asset's folder that is there already is left as it is (it
  may hold the user's work); deleting it brings the latest version back at the next start.
- `library/common/<kind>/<name>/`: the latest version of each `common` asset, replaced at
  each start, files 0o444 and folders 0o555.

Copies, never hard links to the library's blobs: the JupyterLab runs as the server's user,
which could write through a link (the mode bits do not stop a file's owner, nor root).
"""

from __future__ import annotations

import asyncio
import os
import shutil
from collections.abc import AsyncIterator
from pathlib import Path

from twinlink.auth.rights import Principal
from twinlink.domain.library import AssetRecord, VersionRecord
from twinlink.library import archive
from twinlink.library.service import LibraryService
from twinlink.workspaces.service import Materializer

PAGE = 500
LATEST = "latest"


def materializer(library: LibraryService) -> Materializer:
    async def fill(principal: Principal, dest: Path) -> None:
        assert principal.user is not None
        await fill_own(library, f"user:{principal.user.username}", dest)
        await fill_common(library, dest / "common")

    return fill


async def fill_own(library: LibraryService, scope: str, dest: Path) -> None:
    async for asset, version in latest_versions(library, scope):
        target = dest / asset.kind / asset.name
        if not target.exists():
            await archive.materialize(version.files, library.blobs, target, link=False)


async def fill_common(library: LibraryService, dest: Path) -> None:
    if dest.exists():
        await asyncio.to_thread(_remove_read_only, dest)
    dest.mkdir(parents=True)
    async for asset, version in latest_versions(library, "common"):
        target = dest / asset.kind / asset.name
        await archive.materialize(version.files, library.blobs, target, link=False)
    await asyncio.to_thread(_make_read_only, dest)


async def latest_versions(
    library: LibraryService, scope: str
) -> AsyncIterator[tuple[AssetRecord, VersionRecord]]:
    """Each asset of `scope` with its `latest` version (assets without one are left out)."""
    after: tuple[str, str, str] | None = None
    while True:
        page = await library.store.list_assets([scope], kind=None, text=None, limit=PAGE,
                                               after=after)  # fmt: skip
        for asset in page:
            digest = asset.tags.get(LATEST)
            version = await library.store.get_version(asset.id, digest) if digest else None
            if version is not None:
                yield asset, version
        if len(page) < PAGE:
            return
        after = (page[-1].scope, page[-1].kind, page[-1].name)


def _make_read_only(root: Path) -> None:
    for folder, _, files in os.walk(root, topdown=False):
        for name in files:
            os.chmod(os.path.join(folder, name), 0o444)
        os.chmod(folder, 0o555)


def _remove_read_only(root: Path) -> None:
    for folder, _, _ in os.walk(root):
        os.chmod(folder, 0o755)
    shutil.rmtree(root)
