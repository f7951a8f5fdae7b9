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
from functools import partial
from pathlib import Path
from typing import Any

from twinlink.domain.errors import StorageError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.db import JOURNAL_SIZE_LIMIT, migrate
from twinlink.store.sqlite.faults import StorageFaults, translate
from twinlink.store.sqlite.history import staging
from twinlink.store.sqlite.history.blocks import MAX_SIGNALS_PER_STREAM, BlockWriter
from twinlink.store.sqlite.history.compact import Compacted

log = logging.getLogger("twinlink.history")

BUSY_TIMEOUT_MS = 10_000
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
        self.wal_limit = JOURNAL_SIZE_LIMIT  # what a deletion lets the WAL grow to
        self.faults = faults or StorageFaults()
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="twinlink-history")
        self._conn: sqlite3.Connection | None = None
        self.blocks = BlockWriter(max_signals_per_stream)
        self._cache = self.blocks.cache
        self._cache.hot_rows = staging.TWIN_FLUSH_ROWS
        self._pending: list[_Append | _Write] = []
        self._wake = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._closing = False
        self._flushing = False  # a move of staged rows is queued or running
        self._draining = False  # moving every staged row, a round at a time
        self._next_flush = 0.0  # no move of staged rows before this (monotonic) time
        self._staged_since: float | None = None  # when rows were first seen staged
        self.commits = 0

    async def open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(self._executor, self._open)
        self._task = asyncio.create_task(self._run(), name="history-writer")

    def _open(self) -> None:
        self._conn = open_connection(self.path, self.synchronous)
        migrate(self._conn, folder_name="history/migrations")
        self.blocks.load(self._conn)

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
        await self._flush_at_close()
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
            if self._cache.staged() and not self._flushing:
                # Staged rows are moved after FLUSH_AFTER_S even when nothing else comes.
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self._wake.wait(), staging.FLUSH_AFTER_S)
            else:
                await self._wake.wait()
            self._wake.clear()
            self._flush_when_due()
            await self._commit_round()

    # -- staged batches (staging.py) --------------------------------------------------------

    def staged(self, twin_id: int | None = None) -> int:
        """Rows staged (committed) for a twin, or for all twins when None."""
        return self._cache.staged(twin_id)

    def _flush_when_due(self) -> None:
        """Queue a move of staged rows when a twin has many, when many wait in all, or when
        the oldest waited long enough (staging.py)."""
        total = self._cache.staged()
        if not total:
            self._staged_since, self._draining = None, False
            return
        now = time.monotonic()
        if self._staged_since is None:
            self._staged_since = now
        if self._flushing or now < self._next_flush:
            return
        twin_id = next(iter(self._cache.hot), None)
        if twin_id is None and not self._draining:
            if total < staging.FLUSH_ROWS and now - self._staged_since < staging.FLUSH_AFTER_S:
                return
            self._draining = True  # round after round until none is staged
        self._flushing = True
        future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        future.add_done_callback(self._flushed)
        self._pending.append(_Write(partial(self.flush_staged, twin_id=twin_id), future))

    def _flushed(self, future: asyncio.Future[Any]) -> None:
        self._flushing = False
        if future.cancelled() or future.exception() is not None:
            self._draining = False  # a disk failure, counted and logged by the round: the
            return  # rows stay staged and are tried again when due again
        # The next one after a gap, so a drain of many is spread over the commits.
        self._next_flush = time.monotonic() + staging.FLUSH_GAP_S
        asyncio.get_running_loop().call_later(staging.FLUSH_GAP_S, self._wake.set)

    async def _flush_at_close(self) -> None:
        """Move every staged row into blocks before closing, so a stopped server leaves none
        (a full disk may leave some: they are moved after the next start)."""
        while self._cache.staged():
            future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
            self._pending.append(_Write(self.flush_staged, future))
            await self._commit_round()
            if future.exception() is not None or not future.result():
                return

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
            self.blocks.write_latest(conn, latest)
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
            result = (
                item.fn(conn)
                if isinstance(item, _Write)
                else self.blocks.store(conn, item.batch, item.device_id, ends)
            )
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

    # -- what the rounds write (blocks.py) --------------------------------------------------

    @property
    def max_signals_per_stream(self) -> int:
        return self.blocks.max_signals_per_stream

    @max_signals_per_stream.setter
    def max_signals_per_stream(self, limit: int) -> None:
        self.blocks.max_signals_per_stream = limit

    def flush_staged(
        self, conn: sqlite3.Connection, twin_id: int | None = None,
        limit: int = staging.FLUSH_ROUND_ROWS,
    ) -> int:  # fmt: skip
        """Move staged rows into blocks (a `write` fn); see BlockWriter.flush_staged."""
        return self.blocks.flush_staged(conn, twin_id, limit)

    def compact(self, conn: sqlite3.Connection, series_id: int, budget: int = 10**18) -> Compacted:
        """Merge the series' small blocks, up to `budget` samples (a `write` fn)."""
        return self.blocks.compact(conn, series_id, budget)

    def take_small_blocks(self) -> set[int]:
        """The series that got small blocks (committed) since the last call."""
        return self.blocks.cache.take_small()

    def forget_series(self, twin_id: int) -> None:
        """Drop cached ids of a twin whose series were deleted, and its staged batches
        (call from a `write` fn)."""
        assert self._conn is not None
        self.blocks.forget_series(self._conn, twin_id)


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return 0
