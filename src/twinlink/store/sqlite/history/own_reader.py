"""A read-only connection to history.db on a thread of its own, for the command log and
device properties: their reads never wait for a group commit, never occupy the writer's
thread, and never queue behind a long history read on the shared read threads."""

from __future__ import annotations

import asyncio
import sqlite3
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import TypeVar

T = TypeVar("T")


class OwnReader:
    """One read-only WAL connection, used from one thread of its own."""

    def __init__(self, path: Path, name: str) -> None:
        self.path = path
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix=name)
        self._conn: sqlite3.Connection | None = None

    async def open(self) -> None:
        def _open() -> None:
            conn = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            conn.execute("PRAGMA query_only=ON")
            conn.execute("PRAGMA busy_timeout=10000")
            self._conn = conn

        await asyncio.get_running_loop().run_in_executor(self._executor, _open)

    async def close(self) -> None:
        def _close() -> None:
            if self._conn is not None:
                self._conn.close()
                self._conn = None

        await asyncio.get_running_loop().run_in_executor(self._executor, _close)
        self._executor.shutdown(wait=True)

    async def read(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        def _run() -> T:
            if self._conn is None:
                raise RuntimeError(f"the reader of {self.path.name} is not open")
            return fn(self._conn)

        return await asyncio.get_running_loop().run_in_executor(self._executor, _run)
