"""One SQLite connection owned by one thread, and versioned schema migrations.

SQLite allows one writer at a time; giving the connection a thread of its own turns every
call into a queue entry instead of a lock fight, and keeps the event loop free. A write the
disk refuses (full, I/O error) leaves as StorageFullError/StorageError (faults.py), one that
breaks a constraint (a unique name) as WriteConflictError: no sqlite3 error leaves the store.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import re
import sqlite3
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from importlib import resources
from pathlib import Path
from typing import TypeVar

from twinlink.domain.errors import StorageError, WriteConflictError
from twinlink.store.sqlite.faults import StorageFaults, translate

T = TypeVar("T")
log = logging.getLogger("twinlink.store")

# After a checkpoint empties the WAL, SQLite trims the file to this size. Without a limit the
# WAL keeps the size of the largest transaction it ever held (a retention run made it 58 MB
# and it stayed so); with it, it comes back to at most this.
JOURNAL_SIZE_LIMIT = 16 * 2**20

_MIGRATION_NAME = re.compile(r"^(\d{4})_[a-z0-9_]+\.sql$")


def migrations(folder_name: str = "migrations") -> list[tuple[int, str, str]]:
    """(version, file name, SQL) of every migration shipped in the package, in order;
    `folder_name` is relative to this package (`history/migrations` for history.db)."""
    folder = resources.files("twinlink.store.sqlite").joinpath(*folder_name.split("/"))
    found = []
    for entry in folder.iterdir():
        match = _MIGRATION_NAME.match(entry.name)
        if match:
            found.append((int(match.group(1)), entry.name, entry.read_text("utf-8")))
    return sorted(found)


def migrate(
    conn: sqlite3.Connection, target: int | None = None, folder_name: str = "migrations"
) -> list[int]:
    """Apply pending migrations in order, each in its own transaction. Returns those applied."""
    current = conn.execute("PRAGMA user_version").fetchone()[0]
    applied = []
    for version, name, sql in migrations(folder_name):
        if version <= current or (target is not None and version > target):
            continue
        # executescript commits first, so wrap the script and the version bump ourselves.
        conn.executescript(f"BEGIN;\n{sql}\nPRAGMA user_version = {version};\nCOMMIT;")
        log.info("schema migrated", extra={"event": "migrate", "version": version, "file": name})
        applied.append(version)
    return applied


def connect(path: Path) -> sqlite3.Connection:
    conn = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
    conn.row_factory = sqlite3.Row
    conn.execute("PRAGMA journal_mode=WAL")
    conn.execute("PRAGMA synchronous=NORMAL")
    conn.execute("PRAGMA foreign_keys=ON")
    conn.execute("PRAGMA busy_timeout=5000")
    conn.execute(f"PRAGMA journal_size_limit={JOURNAL_SIZE_LIMIT}")
    return conn


class Database:
    """Runs functions against the connection on its own thread."""

    def __init__(self, path: Path, faults: StorageFaults | None = None) -> None:
        self.path = path
        self.faults = faults or StorageFaults()
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="twinlink-sqlite")
        self._conn: sqlite3.Connection | None = None

    async def open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)

        def _open() -> None:
            self._conn = connect(self.path)
            migrate(self._conn)

        await self.run(_open)

    async def close(self) -> None:
        def _close() -> None:
            if self._conn is None:
                return
            try:
                self._conn.execute("PRAGMA optimize")  # statistics for the query planner
            except sqlite3.Error as err:  # a full disk: they are only a hint; close anyway
                log.warning("store: skipped PRAGMA optimize at close: %s", err,
                            extra={"event": "store_close"})  # fmt: skip
            self._conn.close()
            self._conn = None

        await self.run(_close)
        self._executor.shutdown(wait=True)

    async def run(self, fn: Callable[..., T], *args: object) -> T:
        loop = asyncio.get_running_loop()
        try:
            return await loop.run_in_executor(self._executor, fn, *args)
        except sqlite3.IntegrityError as err:
            raise WriteConflictError() from err
        except sqlite3.OperationalError as err:
            mapped = translate(err)
            if not isinstance(mapped, StorageError):
                raise
            self.faults.failed(mapped, self.path.name, "metadata write")
            raise mapped from err

    @property
    def conn(self) -> sqlite3.Connection:
        if self._conn is None:
            raise RuntimeError("the store is not open")
        return self._conn

    async def read(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        return await self.run(fn, self.conn)

    async def write(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """Run `fn` in one transaction: all of its writes land, or none do."""

        def _tx(conn: sqlite3.Connection) -> T:
            if conn.in_transaction:  # a ROLLBACK that failed last time left one open
                conn.execute("ROLLBACK")
            conn.execute("BEGIN IMMEDIATE")
            try:
                result = fn(conn)
                conn.execute("COMMIT")
            except BaseException:
                # On a full disk SQLite may have rolled back already; a ROLLBACK then would
                # only hide the error that matters.
                if conn.in_transaction:
                    with contextlib.suppress(sqlite3.Error):
                        conn.execute("ROLLBACK")
                raise
            return result

        result = await self.run(_tx, self.conn)
        self.faults.ok(self.path.name)
        return result


def next_id(conn: sqlite3.Connection, table: str) -> int:
    """A fresh id for `table` that was never used before (migration 0004), even after the row
    with the largest id is deleted. Call inside the write transaction that inserts the row."""
    row = conn.execute(
        "UPDATE id_counters SET next = next + 1 WHERE name = ? RETURNING next - 1", (table,)
    ).fetchone()
    return int(row[0])
