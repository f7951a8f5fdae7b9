"""Unpacking a spooled tar, tgz or zip archive into blobs, entry by entry, in a worker thread.

Everything an archive says is distrusted: entries are checked before a byte of theirs is
written (paths, types, how many), sizes are counted on the bytes really unpacked (a zip bomb
says its entry is small), and a gzip stream is read through `_Guard`, which refuses to
decompress past the limit (a tar header of a gigabyte is read into memory by tarfile).
Each file goes to a temporary file of the blob store, hashed as it is written; on any refusal
every temporary file is removed, so nothing is left behind.
"""

from __future__ import annotations

import contextlib
import gzip
import hashlib
import io
import os
import stat
import struct
import tarfile
import zipfile
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from twinlink.domain.errors import InvalidInputError, PayloadTooLargeError
from twinlink.domain.library import FileEntry
from twinlink.library.blobs import CHUNK, BlobStore
from twinlink.library.manifest import Limits, check_path, check_unique

# What a tgz may decompress to besides its files' bytes: tar's headers, at most a few blocks
# an entry (long names, PAX records), and its end-of-archive padding.
HEADER_ALLOWANCE = 4096
# The errors of a malformed archive, as the readers raise them (a disk error is an OSError
# of another kind and stays one).
_BROKEN = (tarfile.TarError, zipfile.BadZipFile, EOFError, zlib.error, gzip.BadGzipFile)


def size_text(n: int) -> str:
    return f"{n // 2**20} MB" if n >= 2**20 else f"{n} bytes"


@dataclass(slots=True)
class Unpacked:
    """The files unpacked so far, each in its temporary file until adopted as its blob."""

    entries: list[FileEntry] = field(default_factory=list)
    temps: list[Path] = field(default_factory=list)
    total: int = 0  # bytes unpacked

    def discard(self) -> None:
        for temp in self.temps:
            temp.unlink(missing_ok=True)
        self.temps.clear()


def unpack(spool: Path, fmt: str, blobs: BlobStore, limits: Limits) -> Unpacked:
    """The files of the archive at `spool` (`fmt` tar, tgz or zip), each in a temporary file
    of `blobs`. Refusals are InvalidInputError (PayloadTooLargeError when over the limit)
    naming the entry; they leave no temporary file."""
    out = Unpacked()
    try:
        if fmt == "zip":
            _unzip(spool, blobs, limits, out)
        else:
            _untar(spool, fmt == "tgz", blobs, limits, out)
        if not out.entries:
            raise InvalidInputError(f"the {fmt} archive holds no files")
        check_unique(e.path for e in out.entries)
    except _BROKEN as err:
        out.discard()
        raise InvalidInputError(f"the body is not a readable {fmt} archive: {err}") from err
    except BaseException:
        out.discard()
        raise
    return out


def _copy(source: IO[bytes], path: str, blobs: BlobStore, limits: Limits, out: Unpacked) -> None:
    """One file's bytes into a temporary file, hashed and counted against the limit."""
    fd, temp = blobs.temp_file()
    out.temps.append(temp)
    digest = hashlib.sha256()
    size = 0
    with os.fdopen(fd, "wb") as sink:
        while data := source.read(CHUNK):
            size += len(data)
            out.total += len(data)
            if out.total > limits.max_bytes:
                raise PayloadTooLargeError(
                    f"entry {path!r}: the archive unpacks to more than the library's limit of "
                    f"{size_text(limits.max_bytes)} (library_max_mb)"
                )
            digest.update(data)
            sink.write(data)
        sink.flush()
        os.fsync(sink.fileno())  # the version that names this blob is committed next
    out.entries.append(FileEntry(path, digest.hexdigest(), size))


def _count(n: int, limits: Limits) -> None:
    if n > limits.max_files:
        raise InvalidInputError(
            f"the archive holds more than {limits.max_files} entries, the library's limit; "
            "pack fewer, larger files (a data set as one archive file, say)"
        )


# -- tar ---------------------------------------------------------------------------------------


def _untar(spool: Path, gz: bool, blobs: BlobStore, limits: Limits, out: Unpacked) -> None:
    with spool.open("rb") as raw, contextlib.ExitStack() as stack:
        source: IO[bytes] = raw
        if gz:
            source = stack.enter_context(gzip.GzipFile(fileobj=raw, mode="rb"))  # type: ignore[arg-type]
        elif _is_gzip(raw):
            raise InvalidInputError("the body is gzip-compressed: push it with format=tgz")
        budget = limits.max_bytes + HEADER_ALLOWANCE * (limits.max_files + 2)
        guarded = _Guard(source, budget)
        with tarfile.open(fileobj=guarded, mode="r:") as tar:
            for n, member in enumerate(_members(tar), start=1):
                _count(n, limits)
                _tar_member(tar, member, blobs, limits, out)


def _members(tar: tarfile.TarFile) -> Iterator[tarfile.TarInfo]:
    while (member := tar.next()) is not None:
        yield member
        tar.members.clear()  # type: ignore[attr-defined]  # tarfile keeps every header it read; nothing here needs them


def _tar_member(
    tar: tarfile.TarFile, member: tarfile.TarInfo, blobs: BlobStore, limits: Limits, out: Unpacked
) -> None:
    if member.isdir():
        check_path(member.name, folder=True)
        return
    path = check_path(member.name)
    if member.issym() or member.islnk():
        kind = "a symbolic link" if member.issym() else "a hard link"
        raise InvalidInputError(
            f"entry {path!r}: {kind} (to {member.linkname!r}); the library keeps regular "
            "files only, so pack the file itself (tar --dereference)"
        )
    if not member.isreg():
        raise InvalidInputError(
            f"entry {path!r}: not a regular file (a device, a FIFO, ...); the library keeps "
            "regular files only"
        )
    if out.total + member.size > limits.max_bytes:
        raise PayloadTooLargeError(
            f"entry {path!r}: the archive unpacks to more than the library's limit of "
            f"{size_text(limits.max_bytes)} (library_max_mb)"
        )
    source = tar.extractfile(member)
    assert source is not None  # a regular file always has its data
    with source:
        _copy(source, path, blobs, limits, out)
    last = out.entries[-1]
    out.entries[-1] = FileEntry(last.path, last.sha256, last.size, bool(member.mode & 0o100))


def _is_gzip(raw: IO[bytes]) -> bool:
    magic = raw.read(2)
    raw.seek(0)
    return magic == b"\x1f\x8b"


class _Guard(io.RawIOBase):
    """A tar stream that refuses a single read of more than CHUNK (tarfile reads a PAX
    header or a long name in one read, into memory), and to go past `budget` bytes (a gzip
    stream decompresses as far as it is read or sought)."""

    def __init__(self, inner: IO[bytes], budget: int) -> None:
        self._inner = inner
        self._budget = budget

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self._inner.tell()

    def seek(self, offset: int, whence: int = os.SEEK_SET) -> int:
        if whence == os.SEEK_CUR:
            offset, whence = self._inner.tell() + offset, os.SEEK_SET
        if whence != os.SEEK_SET or offset > self._budget:
            self._refuse("the archive goes on past the library's limit")
        return self._inner.seek(offset)

    def read(self, size: int | None = -1) -> bytes:
        if size is None or size < 0 or size > CHUNK:
            self._refuse("a tar header is over 1 MB")
        data = self._inner.read(size)  # type: ignore[arg-type]  # size checked above
        if self._inner.tell() > self._budget:
            self._refuse("the archive goes on past the library's limit")
        return data

    def _refuse(self, why: str) -> None:
        raise PayloadTooLargeError(
            f"{why} of {size_text(self._budget)} unpacked, headers included (library_max_mb)"
        )


# -- zip ---------------------------------------------------------------------------------------


def _unzip(spool: Path, blobs: BlobStore, limits: Limits, out: Unpacked) -> None:
    # zipfile reads the whole central directory into memory when it opens the file: its
    # entry count is checked first, from the end record.
    _count(_zip_entries(spool), limits)
    with zipfile.ZipFile(spool) as archive:
        infos = archive.infolist()
        _count(len(infos), limits)
        for info in infos:
            _zip_member(archive, info, blobs, limits, out)


def _zip_entries(spool: Path) -> int:
    """The entry count of the zip's end of central directory record (0 when it has none or
    says 0xFFFF, zip64's marker: zipfile then reads the zip64 record and refuses what is
    broken, and the count is checked again once read)."""
    with spool.open("rb") as raw:
        raw.seek(0, os.SEEK_END)
        size = raw.tell()
        tail_size = min(size, 22 + 0xFFFF)
        raw.seek(size - tail_size)
        tail = raw.read(tail_size)
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < 22:
        return 0
    total: int = struct.unpack_from("<H", tail, at + 10)[0]
    return 0 if total == 0xFFFF else total


def _zip_member(
    archive: zipfile.ZipFile,
    info: zipfile.ZipInfo,
    blobs: BlobStore,
    limits: Limits,
    out: Unpacked,
) -> None:
    mode = info.external_attr >> 16 if info.create_system == 3 else 0  # 3: unix
    kind = stat.S_IFMT(mode)
    if info.is_dir():
        check_path(info.filename, folder=True)
        return
    path = check_path(info.orig_filename)
    if kind == stat.S_IFLNK:
        raise InvalidInputError(
            f"entry {path!r}: a symbolic link; the library keeps regular files only, so pack "
            "the file itself (zip without --symlinks)"
        )
    if kind not in (0, stat.S_IFREG):
        raise InvalidInputError(
            f"entry {path!r}: not a regular file (a device, a FIFO, ...); the library keeps "
            "regular files only"
        )
    if info.flag_bits & 0x1:
        raise InvalidInputError(f"entry {path!r}: encrypted; push the archive unencrypted")
    try:
        source = archive.open(info)
    except NotImplementedError as err:  # a compression method zipfile cannot read
        raise InvalidInputError(f"entry {path!r}: {err}; use deflate or store") from err
    with source:
        _copy(source, path, blobs, limits, out)
    last = out.entries[-1]
    out.entries[-1] = FileEntry(last.path, last.sha256, last.size, bool(mode & 0o100))
