"""Run logs: one file per run, `data_dir/runs/<id>.log`, kept after the run (all runs' logs
are kept). The script writes it directly (runner.py); these read it, from any offset, while
it grows."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path

CHUNK = 64 * 1024  # bytes read at a time
# How often a follower looks for more: the script writes the file itself, nothing tells us.
FOLLOW_POLL_S = 0.2


def log_path(root: Path, run_id: int) -> Path:
    return root / f"{run_id}.log"


def _read(path: Path, offset: int, size: int) -> bytes:
    try:
        with path.open("rb") as file:
            file.seek(offset)
            return file.read(size)
    except FileNotFoundError:  # not started yet (or its node's disk is another)
        return b""


def size_of(path: Path) -> int:
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return 0


def append_line(path: Path, text: str) -> None:
    """The platform's own word in a run's log (how it ended): a line of its own."""
    with path.open("ab") as file:
        if file.tell() and _read(path, file.tell() - 1, 1) != b"\n":
            file.write(b"\n")
        file.write(f"[twinlink] {text}\n".encode())


async def read_range(path: Path, offset: int, end: int | None = None) -> AsyncIterator[bytes]:
    """The log from `offset` to `end` (None: its size now), in chunks."""
    end = size_of(path) if end is None else end
    while offset < end:
        chunk = await asyncio.to_thread(_read, path, offset, min(CHUNK, end - offset))
        if not chunk:
            return
        offset += len(chunk)
        yield chunk


async def follow(
    path: Path, offset: int, ended: Callable[[], Awaitable[bool]]
) -> AsyncIterator[bytes]:
    """The log from `offset` as it is written, until the run has `ended` and all of it was
    given."""
    while True:
        done = await ended()  # asked before reading: what was written before the end is read
        chunk = await asyncio.to_thread(_read, path, offset, CHUNK)
        if chunk:
            offset += len(chunk)
            yield chunk
            continue
        if done:
            return
        await asyncio.sleep(FOLLOW_POLL_S)
