"""The library's file contents, kept once each by their SHA-256 (content-addressed).

A version of an asset is a list of files, each naming its blob; two versions (or two assets)
holding the same bytes share one blob. `BlobStore` is the seam an S3-compatible store would
fill later: every write goes through a local temporary file (`temp_file`, then `adopt` once
it is complete and hashed), every read through `read` or `local_path`, so a store that keeps
blobs elsewhere can download to a local cache in `local_path` and upload in `adopt`.
`FileBlobStore`, the only one today, keeps them under the data directory.
"""

from __future__ import annotations

import asyncio
import os
import re
import tempfile
import time
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Protocol

from twinlink.domain.errors import InvalidInputError, NotFoundError

SHA256_HEX = re.compile(r"^[0-9a-f]{64}$")
CHUNK = 1 << 20
# A temporary file older than this is left over from a process that died mid-upload.
STALE_TEMP_S = 24 * 3600


class BlobStore(Protocol):
    """Blobs by their SHA-256 (64 lower-case hex digits)."""

    def temp_file(self) -> tuple[int, Path]:
        """A new, empty temporary file, open for writing (its fd, owned by the caller, and
        its path), where `adopt` can take it in without copying."""
        ...

    async def adopt(self, temp: Path, sha256: str) -> None:
        """Take in the fully written file `temp` as blob `sha256` (the caller hashed it);
        `temp` is gone afterwards. A blob already there is kept and `temp` removed."""
        ...

    async def local_path(self, sha256: str) -> Path:
        """A readable local file of the blob (NotFoundError when there is none)."""
        ...

    def read(self, sha256: str, chunk: int = CHUNK) -> AsyncIterator[bytes]:
        """The blob's bytes, `chunk` at a time."""
        ...

    async def delete(self, sha256: str) -> None:
        """Remove the blob (nothing happens when there is none)."""
        ...

    async def exists(self, sha256: str) -> bool: ...


class FileBlobStore(BlobStore):
    """Blobs as read-only files `root/ab/cdef...` (the hex digest split 2/62, so no folder
    holds more than a 256th of them), temporary files in `root/tmp` on the same file system
    (so adopting one is a rename)."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self.temp_dir = self.root / "tmp"

    def path(self, sha256: str) -> Path:
        if not SHA256_HEX.match(sha256):
            # Only ever called with digests the library computed or checked; a bad one here is
            # a bug, refused before it becomes a path.
            raise InvalidInputError(f"{sha256!r} is not a SHA-256 digest (64 lower-case hex)")
        return self.root / sha256[:2] / sha256[2:]

    def temp_file(self) -> tuple[int, Path]:
        self.temp_dir.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(dir=self.temp_dir, prefix="upload-")
        return fd, Path(name)

    async def adopt(self, temp: Path, sha256: str) -> None:
        target = self.path(sha256)
        try:
            if target.exists():
                return
            target.parent.mkdir(parents=True, exist_ok=True)
            # Read-only: a blob is shared by every version holding these bytes, and a file
            # materialized by a hard link is this very file.
            os.chmod(temp, 0o444)
            os.replace(temp, target)  # atomic: two uploads of the same bytes both succeed
        finally:
            temp.unlink(missing_ok=True)

    async def local_path(self, sha256: str) -> Path:
        path = self.path(sha256)
        if not path.is_file():
            raise NotFoundError(f"the library's blob {sha256} is missing from {self.root}")
        return path

    async def read(self, sha256: str, chunk: int = CHUNK) -> AsyncIterator[bytes]:
        path = await self.local_path(sha256)
        with path.open("rb") as source:
            while data := await asyncio.to_thread(source.read, chunk):
                yield data

    async def delete(self, sha256: str) -> None:
        self.path(sha256).unlink(missing_ok=True)

    async def exists(self, sha256: str) -> bool:
        return self.path(sha256).is_file()

    def remove_stale_temps(self, older_than_s: float = STALE_TEMP_S) -> int:
        """Remove temporary files left by a process that died mid-upload (at start); returns
        how many. Files younger than `older_than_s` may belong to a running upload."""
        if not self.temp_dir.is_dir():
            return 0
        deadline = time.time() - older_than_s
        removed = 0
        for temp in self.temp_dir.iterdir():
            try:
                if temp.stat().st_mtime < deadline:
                    temp.unlink()
                    removed += 1
            except FileNotFoundError:
                continue  # removed meanwhile by its own upload
        return removed
