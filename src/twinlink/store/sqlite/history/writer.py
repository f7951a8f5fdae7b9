"""Group commit: every batch that arrives while a commit is running goes into the next one.

One thread owns the write connection. Callers await `append`, which resolves only after the
transaction holding their batch has committed (with `synchronous=FULL` by default, so an
acknowledged batch survives a power cut, not only a process crash). Under load, commits grow
instead of queueing: a thousand devices cost one fsync per round, not a thousand.

A round that fails (a full disk at COMMIT) fails every caller in it, and nothing the round
cached survives it (series_cache.py); a batch that fails alone (too many signals) fails only
its caller. Disk failures leave as StorageFullError/StorageError, counted and logged once a
minute (faults.py), so a full disk does not also fill the log.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import sqlite3
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import orjson

from twinlink.domain.errors import StorageError, TooManySignalsError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.db import JOURNAL_SIZE_LIMIT, migrate
from twinlink.store.sqlite.faults import StorageFaults, translate
from twinlink.store.sqlite.history.codec import (
    INSERT_BLOCK,
    Block,
    block_row,
    encode,
    split_signals,
)
from twinlink.store.sqlite.history.compact import SMALL, Compacted, compact_series
from twinlink.store.sqlite.history.series_cache import Entry, Key, SeriesCache

log = logging.getLogger("twinlink.history")

BUSY_TIMEOUT_MS = 10_000
# Distinct signals a stream may have (TWINLINK_MAX_SIGNALS_PER_STREAM): far above any real
# device's, low enough that a device sending a new name with every sample by mistake is
# stopped before its stream is too wide to read back in one piece.
MAX_SIGNALS_PER_STREAM = 1_000
WAL_WAIT_S = 60.0  # how long a deletion waits for readers to let the WAL be emptied
WAL_POLL_S = 0.5

WriteFn = Callable[[sqlite3.Connection], Any]


@dataclass(slots=True)
class _Append:
    batch: SampleBatch
    device_id: int | None
    future: asyncio.Future[bool]


@dataclass(slots=True)
class _Write:
    fn: WriteFn
    future: asyncio.Future[Any]


def open_connection(path: Path, synchronous: str) -> sqlite3.Connection:
    conn = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
    conn.execute("PRAGMA journal_mode=WAL")
    conn.execute(f"PRAGMA synchronous={'FULL' if synchronous == 'full' else 'NORMAL'}")
    conn.execute("PRAGMA foreign_keys=ON")
    conn.execute(f"PRAGMA busy_timeout={BUSY_TIMEOUT_MS}")
    conn.execute(f"PRAGMA journal_size_limit={JOURNAL_SIZE_LIMIT}")
    return conn


class HistoryWriter:
    def __init__(
        self,
        path: Path,
        synchronous: str = "full",
        max_signals_per_stream: int = MAX_SIGNALS_PER_STREAM,
        faults: StorageFaults | None = None,
    ) -> None:
        self.path = path
        self.synchronous = synchronous
        self.max_signals_per_stream = max_signals_per_stream
        self.wal_limit = JOURNAL_SIZE_LIMIT  # what a deletion lets the WAL grow to
        self.faults = faults or StorageFaults()
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="twinlink-history")
        self._conn: sqlite3.Connection | None = None
        self._cache = SeriesCache()
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
        self._cache.load(
            self._conn.execute("SELECT id, twin_id, stream, signal, max_span_ns FROM series")
        )

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
        if self._conn is None:
            return
        try:
            self._conn.execute("PRAGMA optimize")  # statistics for the query planner
        except sqlite3.Error as err:  # a full disk: they are only a hint; close anyway
            log.warning("history: skipped PRAGMA optimize at close: %s", err,
                        extra={"event": "history_close"})  # fmt: skip
        self._conn.close()
        self._conn = None

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        """Store `batch` durably. False when this device's `seq` was stored before.
        Raises TooManySignalsError (nothing stored) when the batch would give its stream
        more than `max_signals_per_stream` signals, StorageError when the disk fails."""
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

    async def checkpoint(self) -> tuple[int, int, int]:
        """Copy the WAL into the database and truncate it to nothing, between group
        commits (after a large deletion); (busy, WAL pages, pages copied) as SQLite says.
        Readers in the middle of a long read make it `busy`: it does not wait for them, and
        `journal_size_limit` trims the WAL once they are done."""
        loop = asyncio.get_running_loop()
        try:
            return await loop.run_in_executor(self._executor, self._checkpoint)
        except sqlite3.Error as err:
            mapped = translate(err)
            if mapped is err:
                raise
            raise mapped from err

    async def make_wal_room(self, wait_s: float = WAL_WAIT_S) -> bool:
        """Between the chunks of a large deletion: while the WAL is past `wal_limit`, empty
        it; while readers keep it from being emptied (a long export holds what it reads),
        wait for them, up to `wait_s`. Otherwise every chunk adds its pages to a WAL that
        cannot be reused (one reader open through a retention run took a 27 MB database's
        WAL to 338 MB). False when it gave up waiting."""
        deadline = time.monotonic() + wait_s
        while _size(self.path.with_name(self.path.name + "-wal")) > self.wal_limit:
            busy, _, _ = await self.checkpoint()
            if not busy:
                return True
            if time.monotonic() >= deadline:
                return False
            await asyncio.sleep(WAL_POLL_S)
        return True

    def _checkpoint(self) -> tuple[int, int, int]:
        conn = self._conn
        assert conn is not None
        conn.execute("PRAGMA busy_timeout=0")  # never hold up the commits behind it
        try:
            busy, pages, copied = conn.execute("PRAGMA wal_checkpoint(TRUNCATE)").fetchone()
        finally:
            conn.execute(f"PRAGMA busy_timeout={BUSY_TIMEOUT_MS}")
        return int(busy), int(pages), int(copied)

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
        except StorageError as err:  # counted and logged calmly; every caller is told
            self.faults.failed(err, self.path.name, "history commit")
            results = [err] * len(items)
        except Exception as err:
            log.exception("history commit failed", extra={"event": "history_commit_failed"})
            results = [err] * len(items)
        else:
            self.faults.ok(self.path.name)
        for item, result in zip(items, results, strict=True):
            if item.future.done():  # the caller went away (cancelled); the data still landed
                continue
            if isinstance(result, BaseException):
                item.future.set_exception(result)
            else:
                item.future.set_result(result)

    def _commit(self, items: list[_Append | _Write]) -> list[Any]:
        """One transaction for `items`; the result (or the error) of each. Raises when the
        transaction as a whole fails: then nothing of it was stored."""
        conn = self._conn
        assert conn is not None
        if conn.in_transaction:  # a ROLLBACK that failed last time left one open
            conn.execute("ROLLBACK")
        results: list[Any] = []
        latest: dict[int, tuple[int, Value]] = {}
        self._cache.begin()
        try:
            conn.execute("BEGIN IMMEDIATE")
            for item in items:
                results.append(self._commit_item(conn, item, latest))
            self._write_latest(conn, latest)
            conn.execute("COMMIT")
        except BaseException as err:
            # Nothing of the round was stored, so nothing it cached may stay (series ids
            # that were never committed would be handed to the next new signals).
            self._cache.abandon()
            if conn.in_transaction:  # on a full disk SQLite may have rolled back already
                with contextlib.suppress(sqlite3.Error):
                    conn.execute("ROLLBACK")
            mapped = translate(err)
            if mapped is err:
                raise
            raise mapped from err
        self._cache.release()
        self.commits += 1
        return results

    def _commit_item(
        self, conn: sqlite3.Connection, item: _Append | _Write, latest: dict[int, tuple[int, Value]]
    ) -> Any:
        """One item in a savepoint of its own, so one that cannot be stored fails alone
        (its error is its result) unless the whole transaction is gone with it."""
        conn.execute("SAVEPOINT item")
        self._cache.begin()
        ends: list[tuple[int, int, Value]] = []
        try:
            result = item.fn(conn) if isinstance(item, _Write) else self._store(conn, item, ends)
            conn.execute("RELEASE item")
        except Exception as err:
            self._cache.rollback()
            if not conn.in_transaction:  # SQLite rolled the whole round back: it fails
                raise
            conn.execute("ROLLBACK TO item")
            conn.execute("RELEASE item")
            mapped = translate(err)
            if isinstance(mapped, StorageError):
                self.faults.failed(mapped, self.path.name, "history batch")
            return mapped
        self._cache.release()
        for series_id, t1, last in ends:
            known = latest.get(series_id)
            if known is None or t1 >= known[0]:
                latest[series_id] = (t1, last)
        return result

    def _store(
        self, conn: sqlite3.Connection, item: _Append, ends: list[tuple[int, int, Value]]
    ) -> bool:
        batch = item.batch
        if item.device_id is not None and batch.seq is not None:
            cursor = conn.execute(
                "INSERT OR IGNORE INTO ingested (device_id, seq, at_ns) VALUES (?, ?, ?)",
                (item.device_id, batch.seq, batch.received_ns),
            )
            if cursor.rowcount == 0:
                return False
        columns = split_signals(batch.times, batch.values)
        get = self._cache.get
        known = [get((batch.twin_id, batch.stream, signal)) for signal in columns]
        if None in known:
            self._check_signals(
                batch, [s for s, k in zip(columns, known, strict=True) if k is None]
            )
        rows = []
        for (signal, (times, values)), entry in zip(columns.items(), known, strict=True):
            block = encode(signal, times, values)
            series_id = self._series_id(conn, (batch.twin_id, batch.stream, signal), entry, block)
            rows.append(block_row(series_id, block))
            ends.append((series_id, block.t1, block.last_v))
            if block.n < SMALL:
                self._cache.note_small(series_id)
        conn.executemany(INSERT_BLOCK, rows)
        return True

    def _check_signals(self, batch: SampleBatch, new: list[str]) -> None:
        """Refuse the whole batch when its `new` signals would give its stream too many."""
        twin_id, stream = batch.twin_id, batch.stream
        total = self._cache.signals(twin_id, stream) + len(new)
        limit = self.max_signals_per_stream
        if total <= limit:
            return
        named = ", ".join(repr(s) for s in new[:3]) + (
            f" and {len(new) - 3} more" if len(new) > 3 else ""
        )
        raise TooManySignalsError(
            f"this batch would give stream {stream!r} of twin {batch.twin!r} {total} signals "
            f"(new: {named}); a stream may have at most {limit} "
            "(the server's TWINLINK_MAX_SIGNALS_PER_STREAM). The batch was not stored."
        )

    def _series_id(
        self, conn: sqlite3.Connection, key: Key, known: Entry | None, block: Block
    ) -> int:
        """The series of `key` (`known`: its cached entry), made or widened for `block`."""
        span = block.t1 - block.t0
        if known is None:
            cursor = conn.execute(
                "INSERT INTO series (twin_id, stream, signal, max_span_ns) VALUES (?, ?, ?, ?)",
                (*key, span),
            )
            assert cursor.lastrowid is not None
            self._cache.add(key, cursor.lastrowid, span)
            return cursor.lastrowid
        series_id, max_span = known
        if span > max_span:
            conn.execute("UPDATE series SET max_span_ns = ? WHERE id = ?", (span, series_id))
            self._cache.widen(key, series_id, span)
        return series_id

    @staticmethod
    def _write_latest(conn: sqlite3.Connection, latest: dict[int, tuple[int, Value]]) -> None:
        conn.executemany(
            "INSERT INTO latest (series_id, t, value) VALUES (?, ?, ?) "
            "ON CONFLICT (series_id) DO UPDATE SET t = excluded.t, value = excluded.value "
            "WHERE excluded.t >= latest.t",
            [(sid, t, orjson.dumps(v).decode()) for sid, (t, v) in latest.items()],
        )

    def compact(self, conn: sqlite3.Connection, series_id: int) -> Compacted:
        """Merge the series' small blocks (a `write` fn); keeps the cached span in step."""
        done = compact_series(conn, series_id)
        if done.max_span_ns:
            row = conn.execute(
                "SELECT twin_id, stream, signal, max_span_ns FROM series WHERE id = ?",
                (series_id,),
            ).fetchone()
            if row is not None:
                self._cache.widen((row[0], row[1], row[2]), series_id, row[3])
        return done

    def take_small_blocks(self) -> set[int]:
        """The series that got small blocks (committed) since the last call."""
        return self._cache.take_small()

    def forget_series(self, twin_id: int) -> None:
        """Drop cached ids of a twin whose series were deleted (call from a `write` fn)."""
        self._cache.forget_twin(twin_id)


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return 0
