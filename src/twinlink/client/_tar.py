"""Folders to tar streams and tar streams to folders, in constant memory.

Packing is a generator (no thread, no temporary file): each file's header, its bytes read a
chunk at a time, its padding. Unpacking refuses what could write outside the destination:
absolute paths, `..`, links and devices; it keeps the executable bit."""

from __future__ import annotations

import os
import stat
import tarfile
from collections.abc import Iterable, Iterator
from pathlib import Path, PurePosixPath

CHUNK = 1 << 20
BLOCK = tarfile.BLOCKSIZE


def folder_files(folder: Path) -> list[tuple[str, Path]]:
    """(path in the archive, file) of every file under `folder`, sorted by path. A link is
    refused (its target could be anywhere); empty folders carry nothing and are left out."""
    found: list[tuple[str, Path]] = []
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        for name in [*dirs, *files]:
            path = Path(root) / name
            if path.is_symlink():
                raise ValueError(
                    f"{path} is a symbolic link: copy the file in its place to push it"
                )
        for name in files:
            path = Path(root) / name
            if not stat.S_ISREG(path.stat().st_mode):
                raise ValueError(f"{path} is not a regular file")
            found.append((path.relative_to(folder).as_posix(), path))
    return sorted(found)


def pack(files: Iterable[tuple[str, Path]]) -> Iterator[bytes]:
    """A tar archive (POSIX pax) of `files`, as chunks of at most CHUNK bytes."""
    for name, path in files:
        with path.open("rb") as f:
            st = os.fstat(f.fileno())
            info = tarfile.TarInfo(name)
            info.size = st.st_size
            info.mode = 0o755 if st.st_mode & stat.S_IXUSR else 0o644
            info.mtime = int(st.st_mtime)
            yield info.tobuf(tarfile.PAX_FORMAT, "utf-8", "surrogateescape")
            left = info.size
            while left:
                chunk = f.read(min(CHUNK, left))
                if not chunk:
                    raise ValueError(f"{path} got shorter while it was read: push it again")
                left -= len(chunk)
                yield chunk
        if info.size % BLOCK:
            yield b"\0" * (BLOCK - info.size % BLOCK)
    yield b"\0" * (2 * BLOCK)  # the end of the archive


class _ChunkReader:
    """A file object over an iterator of byte chunks, for tarfile's stream mode (which reads
    a record at a time): each chunk is sliced where it lies, never copied into a growing
    buffer."""

    def __init__(self, chunks: Iterator[bytes]) -> None:
        self.chunks = chunks
        self.chunk = memoryview(b"")

    def read(self, size: int = -1) -> bytes:
        parts: list[bytes] = []
        wanted = size
        while wanted != 0:
            if not self.chunk:
                following = next(self.chunks, None)
                if following is None:
                    break
                self.chunk = memoryview(following)
                continue
            take = len(self.chunk) if wanted < 0 else min(wanted, len(self.chunk))
            parts.append(bytes(self.chunk[:take]))
            self.chunk = self.chunk[take:]
            wanted = wanted - take if wanted > 0 else wanted
        return b"".join(parts)


def safe_member_path(name: str) -> PurePosixPath:
    """The member's path relative to the destination; ValueError for one that could land
    outside it."""
    path = PurePosixPath(name)
    if not name or "\\" in name or "\0" in name or path.is_absolute() or ".." in path.parts:
        raise ValueError(f"the archive holds an unsafe path {name!r}: nothing more is unpacked")
    return path


def unpack(chunks: Iterator[bytes], dest: Path) -> list[str]:
    """Unpack the tar stream `chunks` under `dest`; the paths of the files written."""
    dest.mkdir(parents=True, exist_ok=True)
    root = dest.resolve()
    written: list[str] = []
    with tarfile.open(fileobj=_ChunkReader(chunks), mode="r|*") as archive:  # type: ignore[call-overload]
        for member in archive:
            relative = safe_member_path(member.name)
            target = root / relative
            if member.isdir():
                target.mkdir(parents=True, exist_ok=True)
                continue
            if not member.isfile():
                raise ValueError(f"the archive holds {member.name!r}, not a file: refused")
            target.parent.mkdir(parents=True, exist_ok=True)
            if not target.parent.resolve().is_relative_to(root):
                raise ValueError(f"{member.name!r} would be written outside {dest}: refused")
            if target.is_symlink():
                target.unlink()  # never written through: the link could point anywhere
            source = archive.extractfile(member)
            assert source is not None
            with target.open("wb") as out:
                while chunk := source.read(CHUNK):
                    out.write(chunk)
            target.chmod(0o755 if member.mode & 0o100 else 0o644)
            written.append(relative.as_posix())
    return written
