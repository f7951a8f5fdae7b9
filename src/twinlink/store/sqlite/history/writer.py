"""Group commit: every batch that arrives while a commit is running goes into the next one.

One thread owns the write connection. Callers await `append`, which resolves only after the
transaction holding their batch has committed (with `synchronous=FULL` by default, so an
acknowledged batch survives a power cut, not only a process crash). Under load, commits grow
instead of queueing: a thousand devices cost one fsync per round, not a thousand.
"""

from __future__ import annotations

import asyncio
import logging
import sqlite3
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import orjson

from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.db import migrate
from twinlink.store.sqlite.history.codec import (
    INSERT_BLOCK,
    Block,
    block_row,
    encode,
    split_signals,
)
from twinlink.store.sqlite.history.compact import SMALL, Compacted, compact_series

log = logging.getLogger("twinlink.history")

WriteFn = Callable[[sqlite3.Connection], Any]


@dataclass(slots=True)
class _Append:
    batch: SampleBatch
    device_id: int | None
    future: asyncio.Future[bool]
    blocks: list[Block] = field(default_factory=list)


@dataclass(slots=True)
class _Write:
    fn: WriteFn
    future: asyncio.Future[Any]


def open_connection(path: Path, synchronous: str) -> sqlite3.Connection:
    conn = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
    conn.execute("PRAGMA journal_mode=WAL")
    conn.execute(f"PRAGMA synchronous={'FULL' if synchronous == 'full' else 'NORMAL'}")
    conn.execute("PRAGMA foreign_keys=ON")
    conn.execute("PRAGMA busy_timeout=10000")
    return conn


class HistoryWriter:
    def __init__(self, path: Path, synchronous: str = "full") -> None:
        self.path = path
        self.synchronous = synchronous
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="twinlink-history")
        self._conn: sqlite3.Connection | None = None
        self._series: dict[tuple[int, str, str], tuple[int, int]] = {}  # -> (id, max span)
        # Series that got small blocks since compaction last looked (compact.py).
        self.small_blocks: set[int] = set()
        self._pending: list[_Append | _Write] = []
        self._wake = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._closing = False
        self.commits = 0

    async def open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(self._executor, self._open)
        self._task = asyncio.create_task(self._run(), name="history-writer")

    def _open(self) -> None:
        self._conn = open_connection(self.path, self.synchronous)
        migrate(self._conn, folder_name="history_migrations")
        rows = self._conn.execute("SELECT id, twin_id, stream, signal, max_span_ns FROM series")
        for sid, twin_id, stream, signal, span in rows:
            self._series[(twin_id, stream, signal)] = (sid, span)

    async def close(self) -> None:
        # Let the running round finish and its callers get their answers, then store
        # whatever was accepted before close; never cancel a round half way.
        self._closing = True
        self._wake.set()
        if self._task is not None:
            await asyncio.gather(self._task, return_exceptions=True)
            self._task = None
        if self._pending:
            await self._commit_round()
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(self._executor, self._close)
        self._executor.shutdown(wait=True)

    def _close(self) -> None:
        if self._conn is not None:
            self._conn.execute("PRAGMA optimize")
            self._conn.close()
            self._conn = None

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        """Store `batch` durably. False when this device's `seq` was stored before."""
        future: asyncio.Future[bool] = asyncio.get_running_loop().create_future()
        self._pending.append(_Append(batch, device_id, future))
        self._wake.set()
        return await future

    async def write(self, fn: WriteFn) -> Any:
        """Run `fn(conn)` inside the next group commit; its result once committed."""
        future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        self._pending.append(_Write(fn, future))
        self._wake.set()
        return await future

    async def _run(self) -> None:
        while not self._closing or self._pending:
            await self._wake.wait()
            self._wake.clear()
            await self._commit_round()

    async def _commit_round(self) -> None:
        items, self._pending = self._pending, []
        if not items:
            return
        loop = asyncio.get_running_loop()
        try:
            results = await loop.run_in_executor(self._executor, self._commit, items)
        except Exception as err:
            log.exception("history commit failed", extra={"event": "history_commit_failed"})
            for item in items:
                if not item.future.done():
                    item.future.set_exception(err)
            return
        for item, result in zip(items, results, strict=True):
            if item.future.done():  # the caller went away (cancelled); the data still landed
                continue
            if isinstance(result, BaseException):
                item.future.set_exception(result)
            else:
                item.future.set_result(result)

    def _commit(self, items: list[_Append | _Write]) -> list[Any]:
        conn = self._conn
        assert conn is not None
        results: list[Any] = []
        latest: dict[int, tuple[int, Value]] = {}
        conn.execute("BEGIN IMMEDIATE")
        try:
            for item in items:
                if isinstance(item, _Write):
                    conn.execute("SAVEPOINT item")
                    try:
                        results.append(item.fn(conn))
                        conn.execute("RELEASE item")
                    except Exception as err:
                        conn.execute("ROLLBACK TO item")
                        conn.execute("RELEASE item")
                        self._reload_series(conn)
                        results.append(err)
                    continue
                # A savepoint per batch: one that cannot be stored fails alone.
                conn.execute("SAVEPOINT item")
                try:
                    results.append(self._store(conn, item, latest))
                    conn.execute("RELEASE item")
                except Exception as err:
                    conn.execute("ROLLBACK TO item")
                    conn.execute("RELEASE item")
                    self._reload_series(conn)
                    results.append(err)
            self._write_latest(conn, latest)
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            self._reload_series(conn)
            raise
        self.commits += 1
        return results

    def _store(
        self, conn: sqlite3.Connection, item: _Append, latest: dict[int, tuple[int, Value]]
    ) -> bool:
        batch = item.batch
        if item.device_id is not None and batch.seq is not None:
            cursor = conn.execute(
                "INSERT OR IGNORE INTO ingested (device_id, seq, at_ns) VALUES (?, ?, ?)",
                (item.device_id, batch.seq, batch.received_ns),
            )
            if cursor.rowcount == 0:
                return False
        rows = []
        ends: list[tuple[int, int, Value]] = []
        for signal, (times, values) in split_signals(batch.times, batch.values).items():
            block = encode(signal, times, values)
            series_id = self._series_id(conn, batch.twin_id, batch.stream, signal, block)
            rows.append(block_row(series_id, block))
            ends.append((series_id, block.t1, block.last_v))
            if block.n < SMALL:
                self.small_blocks.add(series_id)
        conn.executemany(INSERT_BLOCK, rows)
        for series_id, t1, last in ends:
            known = latest.get(series_id)
            if known is None or t1 >= known[0]:
                latest[series_id] = (t1, last)
        return True

    def _series_id(
        self, conn: sqlite3.Connection, twin_id: int, stream: str, signal: str, block: Block
    ) -> int:
        key = (twin_id, stream, signal)
        span = block.t1 - block.t0
        known = self._series.get(key)
        if known is None:
            cursor = conn.execute(
                "INSERT INTO series (twin_id, stream, signal, max_span_ns) VALUES (?, ?, ?, ?)",
                (twin_id, stream, signal, span),
            )
            assert cursor.lastrowid is not None
            self._series[key] = (cursor.lastrowid, span)
            return cursor.lastrowid
        series_id, max_span = known
        if span > max_span:
            conn.execute("UPDATE series SET max_span_ns = ? WHERE id = ?", (span, series_id))
            self._series[key] = (series_id, span)
        return series_id

    @staticmethod
    def _write_latest(conn: sqlite3.Connection, latest: dict[int, tuple[int, Value]]) -> None:
        conn.executemany(
            "INSERT INTO latest (series_id, t, value) VALUES (?, ?, ?) "
            "ON CONFLICT (series_id) DO UPDATE SET t = excluded.t, value = excluded.value "
            "WHERE excluded.t >= latest.t",
            [(sid, t, orjson.dumps(v).decode()) for sid, (t, v) in latest.items()],
        )

    def _reload_series(self, conn: sqlite3.Connection) -> None:
        # A rolled-back round may have cached series ids that were never committed.
        self._series.clear()
        rows = conn.execute("SELECT id, twin_id, stream, signal, max_span_ns FROM series")
        for sid, twin_id, stream, signal, span in rows:
            self._series[(twin_id, stream, signal)] = (sid, span)

    def compact(self, conn: sqlite3.Connection, series_id: int) -> Compacted:
        """Merge the series' small blocks (a `write` fn); keeps the cached span in step."""
        done = compact_series(conn, series_id)
        if done.max_span_ns:
            for key, (sid, span) in self._series.items():
                if sid == series_id and done.max_span_ns > span:
                    self._series[key] = (sid, done.max_span_ns)
                    break
        return done

    def take_small_blocks(self) -> set[int]:
        taken, self.small_blocks = self.small_blocks, set()
        return taken

    def forget_series(self, twin_id: int) -> None:
        """Drop cached ids of a twin whose series were deleted (call from a `write` fn)."""
        for key in [k for k in self._series if k[0] == twin_id]:
            del self._series[key]
