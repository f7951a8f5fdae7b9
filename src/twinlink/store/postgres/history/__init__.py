"""Time series in PostgreSQL (`HistoryStore`, store/history.py), for the scale-out setup.

One row per value in `samples`, partitioned by time (partitions.py); the batches that wait
written together, one transaction with one COPY (group.py, batch by batch in writer.py when
one of them fails the group); reads, aggregates, downsampling and exports in SQL
(reads.py, aggregate.py, downsample.py, export.py); retention drops whole partitions
(upkeep.py). Every read sees every batch whose `append` returned: it committed first.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

from twinlink.domain.history import Aggregated, Compaction, Downsampled, SamplePage
from twinlink.domain.samples import SampleBatch
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history import reads, upkeep
from twinlink.store.postgres.history.aggregate import aggregate
from twinlink.store.postgres.history.budget import ReadLimits, reading
from twinlink.store.postgres.history.downsample import downsample
from twinlink.store.postgres.history.export import export_pieces
from twinlink.store.postgres.history.group import GroupCommit
from twinlink.store.postgres.history.published import PublishedMarks
from twinlink.store.postgres.history.series import select_series
from twinlink.store.postgres.history.writer import MAX_SIGNALS_PER_STREAM, HistoryWriter

__all__ = ["PostgresHistory", "ReadLimits"]


class PostgresHistory:
    def __init__(
        self,
        db: PostgresDatabase,
        *,
        max_signals_per_stream: int = MAX_SIGNALS_PER_STREAM,
        limits: ReadLimits | None = None,
    ) -> None:
        self.db = db
        self.writer = HistoryWriter(db, max_signals_per_stream)
        self.groups = GroupCommit(self.writer)
        self.marks = PublishedMarks(db)
        self.limits = limits or ReadLimits()

    async def open(self) -> None:
        """Nothing of its own to open: the shared database is opened before it."""

    async def close(self) -> None:
        """Answers the appends queued and writes the published marks still pending; the
        shared database is closed after."""
        await self.groups.close()
        await self.marks.close()

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        return await self.groups.append(batch, device_id)

    async def unpublished(self, device_id: int, seq: int) -> bool:
        return await self.marks.unpublished(device_id, seq)

    def published(self, device_id: int, seq: int) -> None:
        self.marks.mark(device_id, seq)

    # -- reads: each in a read-only transaction, under a budget of time and values -------

    async def streams(self, twin_id: int) -> list[dict[str, Any]]:
        async with reading(self.db, self.limits.query()) as conn:
            return await reads.stream_summaries(conn, twin_id)

    async def latest(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> dict[str, dict[str, Any]]:
        async with reading(self.db, self.limits.query()) as conn:
            found = await select_series(conn, twin_id, stream, signals)
            return await reads.latest_values(conn, found)

    async def extent(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> tuple[int, int] | None:
        async with reading(self.db, self.limits.query()) as conn:
            found = await select_series(conn, twin_id, stream, signals)
            return await reads.data_extent(conn, found)

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
        async with reading(self.db, self.limits.query()) as conn:
            found = await select_series(conn, twin_id, stream, signals)
            return await reads.sample_page(conn, found, start, end, limit, after)

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
        budget = self.limits.query()
        async with reading(self.db, budget) as conn:
            found = await select_series(conn, twin_id, stream, signals)
            return await aggregate(conn, found, start, end, width, fns, budget)

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
        budget = self.limits.query()
        async with reading(self.db, budget) as conn:
            found = await select_series(conn, twin_id, stream, signals)
            return await downsample(conn, found, start, end, points, method, budget)

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
        """The series are looked up first, so an unknown stream or signal fails before
        anything is sent; the pieces come a page at a time (export.py), until the export's
        time is up (TWINLINK_HISTORY_EXPORT_TIMEOUT_S)."""
        async with reading(self.db, self.limits.query()) as conn:
            found = await select_series(conn, twin_id, stream, signals)
        budget = self.limits.export()
        return found.names, export_pieces(self.db, found, start, end, fmt, time_format, budget)

    # -- upkeep -------------------------------------------------------------------------

    async def twin_ids(self) -> set[int]:
        async with self.db.connection() as conn:
            rows = await conn.fetch("SELECT DISTINCT twin_id FROM streams")
        return {int(r[0]) for r in rows}

    async def compact(self) -> Compaction:
        """Nothing to compact: PostgreSQL's autovacuum keeps the tables tidy."""
        return Compaction()

    async def delete_before(self, cutoff_ns: int) -> int:
        async with self.db.connection() as conn:
            return await upkeep.delete_before(conn, cutoff_ns)

    async def forget_ingested_before(self, cutoff_ns: int) -> int:
        async with self.db.connection() as conn:
            return await upkeep.forget_ingested_before(conn, cutoff_ns)

    async def delete_twin(self, twin_id: int) -> int:
        async with self.db.connection() as conn:
            deleted = await upkeep.delete_twin(conn, twin_id)
        self.writer.forget(twin_id)
        return deleted

    async def reclaim_space(self) -> None:
        """Nothing to do: dropped partitions gave their files back; autovacuum does the
        rest."""
