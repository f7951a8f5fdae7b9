"""Read connections of the history file, on threads of their own.

WAL lets readers run while the writer commits, so reads never wait for a group commit and
never run on the writer's thread. A call borrows one pooled connection for its length; a
stream (an export, which lasts as long as its client reads) gets a connection of its own and
runs one step at a time on the read threads.
"""

from __future__ import annotations

import asyncio
import sqlite3
import threading
from collections.abc import AsyncIterator, Callable, Generator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Generic, TypeVar

T = TypeVar("T")
READ_THREADS = 4


def open_read_connection(path: Path) -> sqlite3.Connection:
    conn = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
    conn.execute("PRAGMA query_only=ON")
    conn.execute("PRAGMA busy_timeout=10000")
    conn.execute("PRAGMA cache_size=-32768")  # 32 MiB of pages per connection
    conn.execute("PRAGMA mmap_size=268435456")  # blobs straight from the page cache
    return conn


class HistoryReader:
    def __init__(self, path: Path, threads: int = READ_THREADS) -> None:
        self.path = path
        self._executor = ThreadPoolExecutor(threads, thread_name_prefix="twinlink-history-read")
        self._lock = threading.Lock()
        self._idle: list[sqlite3.Connection] = []
        self._closed = False

    async def run(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """`fn(conn)` on a read thread with a pooled connection, in one read transaction."""
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self._executor, self._call, fn)

    def _call(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        with self._lock:
            conn = self._idle.pop() if self._idle else None
        if conn is None:
            conn = open_read_connection(self.path)
        try:
            # One snapshot for the whole call: queries that build on each other (summaries,
            # then the blocks they name) see the same blocks even while retention deletes.
            conn.execute("BEGIN")
            try:
                return fn(conn)
            finally:
                conn.execute("ROLLBACK")
        finally:
            with self._lock:
                if self._closed:
                    conn.close()
                else:
                    self._idle.append(conn)

    async def stream(
        self, make: Callable[[sqlite3.Connection], Generator[T, None, None]]
    ) -> AsyncIterator[T]:
        """The items of `make(conn)`, produced on the read threads with a connection of its
        own; closed (generator and connection) when the consumer stops early too."""
        loop = asyncio.get_running_loop()
        steps: _Steps[T] = _Steps(self.path, make)
        try:
            while True:
                item = await loop.run_in_executor(self._executor, steps.next)
                if not item:
                    return
                yield item[0]
        finally:
            try:
                self._executor.submit(steps.close)  # after a step still running, by its lock
            except RuntimeError:  # the executor is shut down: nothing runs any more
                steps.close()

    async def close(self) -> None:
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(None, self._executor.shutdown, True)
        with self._lock:
            self._closed = True
            idle, self._idle = self._idle, []
        for conn in idle:
            conn.close()


class _Steps(Generic[T]):
    """One stream's generator and connection; `next` and `close` never overlap."""

    def __init__(
        self, path: Path, make: Callable[[sqlite3.Connection], Generator[T, None, None]]
    ) -> None:
        self._path = path
        self._make = make
        self._lock = threading.Lock()
        self._conn: sqlite3.Connection | None = None
        self._items: Generator[T, None, None] | None = None
        self._closed = False

    def next(self) -> tuple[T, ...]:
        """The next item, or () at the end."""
        with self._lock:
            if self._closed:
                return ()
            if self._items is None:
                self._conn = open_read_connection(self._path)
                self._items = self._make(self._conn)
            try:
                return (next(self._items),)
            except StopIteration:
                return ()

    def close(self) -> None:
        with self._lock:
            self._closed = True
            if self._items is not None:
                self._items.close()
            if self._conn is not None:
                self._conn.close()
            self._items = self._conn = None
