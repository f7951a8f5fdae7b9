"""A library version's files in and out: `receive` an upload (a tar, tgz or zip archive, or
one plain file) into blobs, `send` a version as an archive, `materialize` it as a folder.

An upload is spooled to a temporary file first, refused as soon as it is over the limit
(the rest of the body is not read), then unpacked in a worker thread (unpack.py): a zip's
directory is at its end, so it cannot be unpacked as it arrives, and one path for every
format is one path to get right. See docs/decisions/0014-library-content-addressed.md.
"""

from __future__ import annotations

import asyncio
import errno
import hashlib
import os
import shutil
from collections.abc import AsyncIterator, Iterable
from pathlib import Path
from typing import Literal, get_args

from twinlink.domain.errors import InvalidInputError, PayloadTooLargeError, StorageFullError
from twinlink.domain.library import FileEntry
from twinlink.library.blobs import CHUNK, BlobStore
from twinlink.library.manifest import Limits, check_path, version_digest
from twinlink.library.pack import send
from twinlink.library.unpack import size_text, unpack

__all__ = [
    "FileEntry",
    "Format",
    "Limits",
    "materialize",
    "receive",
    "send",
    "version_digest",
]

Format = Literal["tar", "tgz", "zip", "file"]
FORMATS: tuple[str, ...] = get_args(Format)


async def receive(
    body: AsyncIterator[bytes],
    fmt: Format,
    blobs: BlobStore,
    limits: Limits,
    filename: str | None = None,
) -> list[FileEntry]:
    """The files of an upload, each kept as its blob in `blobs` (sorted by path). `fmt`
    "file" is one file, named `filename`. Refused (InvalidInputError naming the entry,
    PayloadTooLargeError over `limits.max_bytes`) leaving no temporary file and no blob."""
    if fmt not in FORMATS:
        raise InvalidInputError(f"unknown format {fmt!r}: use one of {', '.join(FORMATS)}")
    name = _file_name(filename) if fmt == "file" else None
    fd, spool = blobs.temp_file()
    try:
        sha256, size = await _spool(fd, body, limits.max_bytes, hashed=name is not None)
        if name is not None:
            await blobs.adopt(spool, sha256)
            return [FileEntry(name, sha256, size)]
        unpacked = await asyncio.to_thread(unpack, spool, fmt, blobs, limits)
        spool.unlink()  # before the blobs are adopted: the disk holds no third copy
        try:
            for entry, temp in zip(unpacked.entries, unpacked.temps, strict=True):
                await blobs.adopt(temp, entry.sha256)
        finally:
            unpacked.discard()
        return sorted(unpacked.entries, key=lambda e: e.path)
    except OSError as err:
        if err.errno == errno.ENOSPC:
            raise StorageFullError("the library's disk is full; nothing was kept") from err
        raise
    finally:
        spool.unlink(missing_ok=True)


def _file_name(filename: str | None) -> str:
    if not filename:
        raise InvalidInputError("format=file needs the file's name: add ?filename=NAME")
    return check_path(filename)


async def _spool(
    fd: int, body: AsyncIterator[bytes], max_bytes: int, hashed: bool
) -> tuple[str, int]:
    """Write the body to `fd` in chunks of about CHUNK bytes (each written, and hashed
    when `hashed`, in a worker thread); refused as soon as it is over `max_bytes`."""
    digest = hashlib.sha256()
    size = 0
    pending: list[bytes] = []
    pending_size = 0
    with os.fdopen(fd, "wb") as out:

        def write(chunks: list[bytes]) -> None:
            for chunk in chunks:
                if hashed:
                    digest.update(chunk)
                out.write(chunk)

        async for chunk in body:
            size += len(chunk)
            if size > max_bytes:
                raise PayloadTooLargeError(
                    f"the upload is over the library's limit of {size_text(max_bytes)} "
                    "(library_max_mb)"
                )
            pending.append(chunk)
            pending_size += len(chunk)
            if pending_size >= CHUNK:
                await asyncio.to_thread(write, pending)
                pending, pending_size = [], 0
        await asyncio.to_thread(write, pending)
        if hashed:  # the spool is the blob: durable before the version naming it is committed
            out.flush()
            await asyncio.to_thread(os.fsync, out.fileno())
    if size == 0:
        raise InvalidInputError("the upload is empty: send the archive (or the file) as the body")
    return digest.hexdigest(), size


async def materialize(
    files: Iterable[FileEntry], blobs: BlobStore, dest: Path, *, link: bool = True
) -> None:
    """Write the version's tree under `dest` (created if missing). A file is a hard link to
    its blob where possible (`link`, same file system: no copy, read-only, as the blob),
    else a copy; executable files are always copies (mode 0o755: the blob's mode is shared
    by every link)."""
    dest = Path(dest)
    for entry in files:
        target = dest / check_path(entry.path)
        source = await blobs.local_path(entry.sha256)
        await asyncio.to_thread(_place, source, target, link and not entry.executable)
        if entry.executable:
            target.chmod(0o755)


def _place(source: Path, target: Path, link: bool) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    target.unlink(missing_ok=True)
    if link:
        try:
            os.link(source, target)
            return
        except OSError as err:
            if err.errno not in (errno.EXDEV, errno.EMLINK, errno.EPERM, errno.ENOTSUP):
                raise
    shutil.copyfile(source, target)
    target.chmod(0o644)
