"""A version sent as a tar, tgz or zip archive, streamed: written by a worker thread into a
`_Pipe` that holds at most DEPTH chunks, read by the event loop as they come, so memory
stays constant whatever the size and a slow client slows the writer instead of filling the
server. The archives are reproducible: files in path order, fixed owner and times, so the
same version is always the same bytes.
"""

from __future__ import annotations

import asyncio
import stat
import tarfile
import threading
import zipfile
import zlib
from collections.abc import AsyncGenerator, Callable, Iterable
from pathlib import Path
from typing import Literal, Protocol

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.library import FileEntry
from twinlink.library.blobs import CHUNK, BlobStore

DEPTH = 4  # chunks between the writer and the client: a few MB at most
# 1980-01-01, the earliest time a zip can hold, for tar too: the same version, the same bytes.
EPOCH = 315_532_800
ZIP_EPOCH = (1980, 1, 1, 0, 0, 0)
# gzip's fastest level: the server's CPU is what is short, and the files that are big are
# mostly compressed already (an FMU is a zip).
GZIP_LEVEL = 1

SendFormat = Literal["tar", "tgz", "zip"]
Sources = list[tuple[FileEntry, Path]]


class Sink(Protocol):
    def write(self, data: bytes) -> int: ...


def send(
    files: Iterable[FileEntry], blobs: BlobStore, fmt: SendFormat
) -> AsyncGenerator[bytes, None]:
    """The archive of `files` (in path order, executable bits kept), as it is written. A
    generator: `aclose` it when the client goes away (the writer stops at once)."""
    writers: dict[str, Callable[[Sources, Sink], None]] = {
        "tar": _write_tar,
        "tgz": _write_tgz,
        "zip": _write_zip,
    }
    if fmt not in writers:
        raise InvalidInputError(f"unknown archive format {fmt!r}: use tar, tgz or zip")
    return _send(sorted(files, key=lambda f: f.path), blobs, writers[fmt])


async def _send(
    files: list[FileEntry], blobs: BlobStore, writer: Callable[[Sources, Sink], None]
) -> AsyncGenerator[bytes, None]:
    sources = [(entry, await blobs.local_path(entry.sha256)) for entry in files]
    pipe = _Pipe(asyncio.get_running_loop())
    worker = asyncio.ensure_future(asyncio.to_thread(pipe.run, lambda: writer(sources, pipe)))
    try:
        while (chunk := await pipe.get()) is not None:
            yield chunk
        await worker  # the writer's error, if it failed
    finally:
        pipe.stop()  # the writer ends at its next chunk when the client went away
        if not worker.done():
            await asyncio.wait([worker])


class _Pipe:
    """Bytes written by one worker thread, read by the event loop, in chunks of about
    CHUNK bytes; the writer waits while DEPTH chunks are unread."""

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        self._queue: asyncio.Queue[bytes | None] = asyncio.Queue()
        self._room = threading.Semaphore(DEPTH)
        self._stopped = threading.Event()
        self._buffer = bytearray()

    # -- the writer's side (a worker thread)

    def run(self, write: Callable[[], None]) -> None:
        try:
            write()
            if self._buffer:
                self._push(bytes(self._buffer))
        except BrokenPipeError:
            pass  # the reader went away (_push): nothing more to write
        finally:
            self._loop.call_soon_threadsafe(self._queue.put_nowait, None)

    def write(self, data: bytes) -> int:
        if not self._buffer and len(data) >= CHUNK:
            self._push(data)
        else:
            self._buffer += data
            if len(self._buffer) >= CHUNK:
                self._push(bytes(self._buffer))
                self._buffer.clear()
        return len(data)

    def flush(self) -> None:
        """zipfile flushes its file; the pipe sends chunks when they are full."""

    def _push(self, chunk: bytes) -> None:
        # A pipe whose reader is gone: the writer unwinds from inside tarfile or zipfile.
        while not self._room.acquire(timeout=0.1):
            if self._stopped.is_set():
                raise BrokenPipeError("the client stopped reading")
        if self._stopped.is_set():
            raise BrokenPipeError("the client stopped reading")
        self._loop.call_soon_threadsafe(self._queue.put_nowait, chunk)

    # -- the reader's side (the event loop)

    async def get(self) -> bytes | None:
        chunk = await self._queue.get()
        if chunk is not None:
            self._room.release()
        return chunk

    def stop(self) -> None:
        self._stopped.set()


def _copy(path: Path, sink: Sink) -> None:
    with path.open("rb") as source:
        while data := source.read(CHUNK):
            sink.write(data)


def _write_tar(sources: Sources, sink: Sink) -> None:
    written = 0
    for entry, path in sources:
        info = tarfile.TarInfo(entry.path)
        info.size = entry.size
        info.mode = 0o755 if entry.executable else 0o644
        info.mtime = EPOCH
        header = info.tobuf(tarfile.PAX_FORMAT, "utf-8", "surrogateescape")
        sink.write(header)
        _copy(path, sink)
        padding = -entry.size % tarfile.BLOCKSIZE
        sink.write(b"\0" * padding)
        written += len(header) + entry.size + padding
    end = 2 * tarfile.BLOCKSIZE
    sink.write(b"\0" * (end + -(written + end) % tarfile.RECORDSIZE))


class _Gzip:
    """A sink that gzips what it is given into another sink."""

    def __init__(self, sink: Sink) -> None:
        self._sink = sink
        self._zip = zlib.compressobj(GZIP_LEVEL, zlib.DEFLATED, 31)  # 31: a gzip header

    def write(self, data: bytes) -> int:
        if out := self._zip.compress(data):
            self._sink.write(out)
        return len(data)

    def close(self) -> None:
        self._sink.write(self._zip.flush())


def _write_tgz(sources: Sources, sink: Sink) -> None:
    gz = _Gzip(sink)
    _write_tar(sources, gz)
    gz.close()


def _write_zip(sources: Sources, sink: Sink) -> None:
    # Written to a sink that cannot seek, zipfile puts each entry's CRC and sizes in a data
    # descriptor after its bytes (and zip64 records where they are needed).
    with zipfile.ZipFile(sink, "w", zipfile.ZIP_STORED) as archive:  # type: ignore[call-overload]
        for entry, path in sources:
            info = zipfile.ZipInfo(entry.path, ZIP_EPOCH)
            info.create_system = 3  # unix: the mode below is read
            mode = 0o755 if entry.executable else 0o644
            info.external_attr = (stat.S_IFREG | mode) << 16
            info.file_size = entry.size
            with archive.open(info, "w") as out, path.open("rb") as source:
                while data := source.read(CHUNK):
                    out.write(data)
