"""Read connections of the history file, on threads of their own.

WAL lets readers run while the writer commits, so reads never wait for a group commit and
never run on the writer's thread. A call borrows one pooled connection for its length; a
stream (an export, which lasts as long as its client reads) gets a connection of its own and
runs one bounded step at a time on the read threads.

Every read has a `ReadBudget`. A stream whose consumer stops is stopped at once (its running
SQL interrupted, its next step never run), so no thread keeps working for a client that left;
`close` stops every read the same way instead of waiting for them to finish.
"""

from __future__ import annotations

import asyncio
import logging
import sqlite3
import threading
from collections.abc import AsyncIterator, Callable, Generator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Generic, TypeVar

from twinlink.domain.history import ReadCancelledError
from twinlink.store.sqlite.history.budget import ReadBudget

T = TypeVar("T")
READ_THREADS = 4
CLOSE_WAIT_S = 3.0  # at most this for reads to notice they were stopped, at shutdown
log = logging.getLogger("twinlink.history")


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
        self._running: set[ReadBudget] = set()
        self._closed = False
        self.steps = 0  # calls and stream steps run so far (a stream's work is countable)
        self.open_streams = 0

    async def run(
        self, fn: Callable[[sqlite3.Connection], T], budget: ReadBudget | None = None
    ) -> T:
        """`fn(conn)` on a read thread with a pooled connection, in one read transaction,
        stopped (ReadBudgetError) when it goes over `budget` or the reader closes."""
        loop = asyncio.get_running_loop()
        try:
            future = loop.run_in_executor(
                self._executor, self._call, fn, budget or ReadBudget(3600.0, 2**62)
            )
        except RuntimeError as err:  # the executor is shut down
            raise ReadCancelledError("the server is shutting down") from err
        return await future

    def _call(self, fn: Callable[[sqlite3.Connection], T], budget: ReadBudget) -> T:
        with self._lock:
            if self._closed:
                raise ReadCancelledError("the server is shutting down")
            conn = self._idle.pop() if self._idle else None
            self._running.add(budget)
            self.steps += 1
        try:
            if conn is None:
                conn = open_read_connection(self.path)
            budget.attach(conn)
            try:
                return _in_transaction(conn, fn, budget)
            finally:
                budget.detach(conn)
        finally:
            with self._lock:
                self._running.discard(budget)
                if conn is not None:
                    if self._closed:
                        conn.close()
                    else:
                        self._idle.append(conn)

    async def stream(
        self, make: Callable[[sqlite3.Connection], Generator[T, None, None]], budget: ReadBudget
    ) -> AsyncIterator[T]:
        """The items of `make(conn)`, produced a step at a time on the read threads with a
        connection of its own. When the consumer stops early (or the task is cancelled), the
        read is stopped at once and its generator and connection closed right after."""
        loop = asyncio.get_running_loop()
        steps: _Steps[T] = _Steps(self, make, budget)
        with self._lock:
            self.open_streams += 1
        try:
            while True:
                try:
                    future = loop.run_in_executor(self._executor, steps.next)
                except RuntimeError as err:  # the executor is shut down
                    raise ReadCancelledError("the server is shutting down") from err
                item = await future
                if not item:
                    return
                yield item[0]
        finally:
            # No await here: a cancelled task would be cancelled again at it. Stopping is
            # immediate; closing waits (on a read thread) for the step that was interrupted.
            budget.stop("the client stopped reading")
            try:
                self._executor.submit(steps.close)
            except RuntimeError:  # the executor is shut down: nothing runs any more
                steps.close()

    def _step_started(self, budget: ReadBudget) -> None:
        with self._lock:
            if self._closed:
                raise ReadCancelledError("the server is shutting down")
            self._running.add(budget)
            self.steps += 1

    def _step_ended(self, budget: ReadBudget) -> None:
        with self._lock:
            self._running.discard(budget)

    def _stream_closed(self) -> None:
        with self._lock:
            self.open_streams -= 1

    async def close(self) -> None:
        """Stop every read (running SQL is interrupted), then wait for the read threads,
        which stop within a step; never for the reads to run to their end."""
        with self._lock:
            self._closed = True
            running = list(self._running)
            idle, self._idle = self._idle, []
        for budget in running:
            budget.stop("the server is shutting down")
        loop = asyncio.get_running_loop()
        # Reads still queued run too, and stop at once: they see the reader closed.
        done = loop.run_in_executor(None, self._executor.shutdown, True)
        try:
            await asyncio.wait_for(asyncio.shield(done), CLOSE_WAIT_S)
        except TimeoutError:
            log.warning(
                "history reads still running at close",
                extra={"event": "history_close", "reads": len(self._running)},
            )
        for conn in idle:
            conn.close()


def _in_transaction(
    conn: sqlite3.Connection, fn: Callable[[sqlite3.Connection], T], budget: ReadBudget
) -> T:
    # One snapshot for the whole call: queries that build on each other (summaries, then
    # the blocks they name) see the same blocks even while retention deletes.
    conn.execute("BEGIN")
    try:
        return fn(conn)
    except sqlite3.OperationalError as err:
        over = budget.explain(err)
        if over is None:
            raise
        raise over from err
    finally:
        conn.execute("ROLLBACK")


class _Steps(Generic[T]):
    """One stream's generator and connection; `next` and `close` never overlap, and `close`
    is quick because the budget was stopped first."""

    def __init__(
        self,
        reader: HistoryReader,
        make: Callable[[sqlite3.Connection], Generator[T, None, None]],
        budget: ReadBudget,
    ) -> None:
        self._reader = reader
        self._make = make
        self._budget = budget
        self._lock = threading.Lock()
        self._conn: sqlite3.Connection | None = None
        self._items: Generator[T, None, None] | None = None
        self._closed = False

    def next(self) -> tuple[T, ...]:
        """The next item, or () at the end."""
        with self._lock:
            if self._closed:
                return ()
            self._reader._step_started(self._budget)
            try:
                self._budget.check()
                if self._items is None:
                    self._conn = open_read_connection(self._reader.path)
                    self._budget.attach(self._conn)
                    self._items = self._make(self._conn)
                try:
                    return (next(self._items),)
                except StopIteration:
                    return ()
                except sqlite3.OperationalError as err:
                    over = self._budget.explain(err)
                    if over is None:
                        raise
                    raise over from err
            finally:
                self._reader._step_ended(self._budget)

    def close(self) -> None:
        with self._lock:
            if self._closed:
                return
            self._closed = True
            try:
                if self._items is not None:
                    self._items.close()
            finally:
                if self._conn is not None:
                    self._budget.detach(self._conn)
                    self._conn.close()
                self._items = self._conn = None
                self._reader._stream_closed()
