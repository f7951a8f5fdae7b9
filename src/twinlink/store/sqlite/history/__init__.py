"""Time series in an embedded SQLite file (`history.db` in the data dir).

The `HistoryStore` of the embedded setup (store/history.py). Writes go through the
group-commit writer (one thread, the only write connection); reads run on their own threads
and connections (`reader.py`). The command log and device properties live in the same file
and share the writer's commits (store/sqlite/commands.py and properties.py use `write`).
"""

from __future__ import annotations

import asyncio
import sqlite3
from collections.abc import AsyncIterator, Callable
from functools import partial
from pathlib import Path
from typing import Any, TypeVar

from twinlink.domain.errors import StorageError
from twinlink.domain.history import Aggregated, Compaction, Downsampled, SamplePage
from twinlink.domain.samples import SampleBatch
from twinlink.store.sqlite.faults import StorageFaults
from twinlink.store.sqlite.history import retention
from twinlink.store.sqlite.history.aggregate import aggregate
from twinlink.store.sqlite.history.blocks import MAX_SIGNALS_PER_STREAM
from twinlink.store.sqlite.history.budget import ReadBudget, ReadLimits
from twinlink.store.sqlite.history.compact import Compacted
from twinlink.store.sqlite.history.downsample import downsample
from twinlink.store.sqlite.history.export import export_pieces
from twinlink.store.sqlite.history.merge import sample_page
from twinlink.store.sqlite.history.queries import data_extent, latest_values, select_series
from twinlink.store.sqlite.history.reader import HistoryReader
from twinlink.store.sqlite.history.streams import stream_summaries
from twinlink.store.sqlite.history.writer import HistoryWriter, WriteFn

T = TypeVar("T")
# About 10-20 ms of work a round: 2 000 tiny blocks (8 us a block), 50 series (each costs
# its statements, some 0.3 ms, however few blocks it has) or 10 000 samples decoded and
# encoded again; and a gap after each, so a backlog of merges (after a fast device's large
# batches) is spread over the commits instead of holding up the acks behind it.
COMPACT_ROUND_BLOCKS = 2_000
COMPACT_ROUND_SERIES = 50
COMPACT_ROUND_SAMPLES = 10_000
COMPACT_GAP_S = 0.02

__all__ = ["ReadLimits", "SqliteHistory"]


class SqliteHistory:
    def __init__(
        self,
        data_dir: Path,
        synchronous: str = "full",
        *,
        max_signals_per_stream: int = MAX_SIGNALS_PER_STREAM,
        faults: StorageFaults | None = None,
        limits: ReadLimits | None = None,
    ) -> None:
        self.path = data_dir / "history.db"
        self.writer = HistoryWriter(self.path, synchronous, max_signals_per_stream, faults)
        self.reader = HistoryReader(self.path)
        self.limits = limits or ReadLimits()

    async def open(self) -> None:
        await self.writer.open()

    async def close(self) -> None:
        await self.reader.close()
        await self.writer.close()

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        return await self.writer.append(batch, device_id)

    async def unpublished(self, device_id: int, seq: int) -> bool:
        # The in-process bus cannot refuse a batch: every stored one was published (or its
        # process ended between the two, and with it every subscriber of the bus).
        return False

    def published(self, device_id: int, seq: int) -> None:
        """Nothing to note: see `unpublished`."""

    async def write(self, fn: WriteFn) -> object:
        """Run `fn(conn)` inside the next group commit; its result once committed (the
        command log and device properties write this way)."""
        return await self.writer.write(fn)

    async def twin_ids(self) -> set[int]:
        """The twins that have series here."""
        rows = await self.reader.run(
            lambda conn: conn.execute("SELECT DISTINCT twin_id FROM series").fetchall()
        )
        return {int(r[0]) for r in rows}

    async def compact(self) -> Compaction:
        """Merge small blocks of the series that got them since the last call, as many
        series per group commit as make about `COMPACT_ROUND_BLOCKS` blocks,
        `COMPACT_ROUND_SERIES` series or `COMPACT_ROUND_SAMPLES` samples (compact.py): each
        commit costs an fsync, and a device fleet gives thousands of such series, but no
        round may hold up ingest for long."""
        total = Compacted()
        pending = sorted(self.writer.take_small_blocks())
        while pending:
            done, pending = await self.writer.write(partial(self._compact_some, series=pending))
            total.blocks_before += done.blocks_before
            total.blocks_after += done.blocks_after
            if pending:
                await asyncio.sleep(COMPACT_GAP_S)
        return Compaction(total.blocks_before, total.blocks_after)

    def _compact_some(
        self, conn: sqlite3.Connection, series: list[int]
    ) -> tuple[Compacted, list[int]]:
        """Compact the first of `series` (a `write` fn) until about COMPACT_ROUND_BLOCKS
        blocks were merged or COMPACT_ROUND_SERIES looked at; the rest are left for the next
        round, so ingest never waits long for one."""
        done = Compacted()
        taken = 0
        while (
            taken < min(len(series), COMPACT_ROUND_SERIES)
            and done.blocks_before < COMPACT_ROUND_BLOCKS
            and done.samples < COMPACT_ROUND_SAMPLES
        ):
            one = self.writer.compact(conn, series[taken], COMPACT_ROUND_SAMPLES - done.samples)
            if not one.more:  # else the series goes on in the next round
                taken += 1
            done.blocks_before += one.blocks_before
            done.blocks_after += one.blocks_after
            done.samples += one.samples
        return done, series[taken:]

    # -- reads: each under a budget of time and values (ReadLimits) ---------------------

    async def settle(self, twin_id: int | None) -> None:
        """Move the twin's staged samples (of every twin when None) into blocks, so a read
        sees every acknowledged sample (staging.py). Nothing to do for most reads. When the
        disk refuses the move (full), the read goes on without the staged samples: reads keep
        working while writes cannot."""
        while self.writer.staged(twin_id):
            try:
                moved = await self.writer.write(partial(self.writer.flush_staged, twin_id=twin_id))
            except StorageError:  # counted and logged by the store
                return
            if not moved:
                return

    async def _read(self, twin_id: int, fn: Callable[[sqlite3.Connection, ReadBudget], T]) -> T:
        await self.settle(twin_id)
        budget = self.limits.query()
        return await self.reader.run(lambda conn: fn(conn, budget), budget)

    async def streams(self, twin_id: int) -> list[dict[str, Any]]:
        """The twin's streams: samples, values, first and last time, and their signals
        (kind, values, first and last time); see streams.py."""
        return await self._read(
            twin_id, lambda conn, budget: stream_summaries(conn, twin_id, budget)
        )

    async def latest(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> dict[str, dict[str, Any]]:
        """{signal: {time, value}} of the newest value of each signal."""
        return await self._read(
            twin_id,
            lambda conn, _: latest_values(conn, select_series(conn, twin_id, stream, signals)),
        )

    async def extent(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> tuple[int, int] | None:
        """(first, last) time of the stored samples of these signals; None when none."""
        return await self._read(
            twin_id,
            lambda conn, _: data_extent(conn, select_series(conn, twin_id, stream, signals)),
        )

    async def samples(
        self,
        twin_id: int,
        stream: str,
        signals: list[str] | None,
        start: int,
        end: int,
        limit: int,
        after: tuple[int, int] | None = None,
    ) -> SamplePage:
        """Up to `limit` rows {time, values} in time order (fewer when they would hold more
        values than the budget); `next_key` continues the page."""

        def run(conn: sqlite3.Connection, budget: ReadBudget) -> Any:
            found = select_series(conn, twin_id, stream, signals)
            return sample_page(conn, found, start, end, limit, after, budget)

        return await self._read(twin_id, run)

    async def aggregate(
        self,
        twin_id: int,
        stream: str,
        signals: list[str] | None,
        start: int,
        end: int,
        width: int,
        fns: list[str],
    ) -> Aggregated:
        """Rows {time: bucket start, values: {signal: {fn: value}}} for buckets of `width` ns
        aligned to the epoch; empty buckets are left out."""

        def run(conn: sqlite3.Connection, budget: ReadBudget) -> Any:
            found = select_series(conn, twin_id, stream, signals)
            return aggregate(conn, found, start, end, width, fns, budget)

        return await self._read(twin_id, run)

    async def downsample(
        self,
        twin_id: int,
        stream: str,
        signals: list[str] | None,
        start: int,
        end: int,
        points: int,
        method: str,
    ) -> dict[str, Downsampled]:
        """Per signal, at most `points` samples that keep the shape (`method` minmax or
        lttb)."""

        def run(conn: sqlite3.Connection, budget: ReadBudget) -> Any:
            found = select_series(conn, twin_id, stream, signals)
            return downsample(conn, found, start, end, points, method, budget)

        return await self._read(twin_id, run)

    async def export(
        self,
        twin_id: int,
        stream: str,
        signals: list[str] | None,
        start: int,
        end: int,
        fmt: str,
        time_format: str,
    ) -> tuple[list[str], AsyncIterator[bytes]]:
        """The signal names, and the range as `fmt` text in pieces. The series are looked up
        first, so an unknown stream or signal fails before anything is sent. The pieces stop
        (ReadBudgetError) when the export runs over its time budget."""
        series = await self._read(
            twin_id, lambda conn, _: select_series(conn, twin_id, stream, signals)
        )
        budget = self.limits.export()
        pieces: AsyncIterator[bytes] = self.reader.stream(
            lambda conn: export_pieces(conn, series, start, end, fmt, time_format, budget),
            budget,
        )
        return [s.signal for s in series], pieces

    # -- deletes (through the writer's group commit, a chunk per commit) ---------------

    async def reclaim_space(self) -> None:
        """Checkpoint the WAL and truncate it (after a large deletion). Readers in the middle
        of a long read make it busy; journal_size_limit trims the WAL once they are done."""
        await self.writer.checkpoint()

    async def _repeat(self, fn: Callable[[Any], int], chunk: int, wal_room: bool = False) -> int:
        total = 0
        while True:
            deleted: int = await self.writer.write(fn)
            total += deleted
            if deleted < chunk:
                return total
            if wal_room:  # retention is never in a hurry: it waits for long reads (once)
                wal_room = await self.writer.make_wal_room()

    async def delete_before(self, cutoff_ns: int, chunk: int = retention.CHUNK) -> int:
        """Delete the samples older than the cutoff (whole blocks whose last sample is older,
        and latest values older); returns the number of blocks deleted."""
        await self.settle(None)
        blocks = await self._repeat(
            partial(retention.delete_blocks_before, cutoff_ns=cutoff_ns, chunk=chunk), chunk, True
        )
        await self.writer.write(partial(retention.delete_latest_before, cutoff_ns=cutoff_ns))
        return blocks

    async def forget_ingested_before(self, cutoff_ns: int, chunk: int = retention.CHUNK) -> int:
        """Forget which batches were stored before the cutoff (the dedupe record)."""
        return await self._repeat(
            partial(retention.delete_ingested_before, cutoff_ns=cutoff_ns, chunk=chunk),
            chunk,
            True,
        )

    async def delete_twin(self, twin_id: int, chunk: int = retention.CHUNK) -> int:
        """Delete all history of a twin; returns the number of blocks deleted."""
        await self.settle(twin_id)
        blocks = await self._repeat(
            partial(retention.delete_twin_blocks, twin_id=twin_id, chunk=chunk), chunk
        )

        def drop_series(conn: Any) -> int:
            count = retention.delete_twin_series(conn, twin_id)
            self.writer.forget_series(twin_id)  # and batches staged meanwhile
            return count

        await self.writer.write(drop_series)
        return blocks
