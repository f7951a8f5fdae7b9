"""Time series in an embedded SQLite file (`history.db` in the data dir).

Writes go through the group-commit writer (one thread, the only write connection); reads run
on their own threads and connections (`reader.py`). Times are ns since the epoch; `start` and
`end` are inclusive, and `queries.MIN_TIME`/`MAX_TIME` stand for "no bound".
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

from twinlink.domain.samples import SampleBatch
from twinlink.store.sqlite.faults import StorageFaults
from twinlink.store.sqlite.history import retention
from twinlink.store.sqlite.history.aggregate import aggregate_rows, aggregate_series
from twinlink.store.sqlite.history.compact import Compacted
from twinlink.store.sqlite.history.downsample import Downsampled, downsample
from twinlink.store.sqlite.history.export import export_pieces
from twinlink.store.sqlite.history.merge import SamplePage, sample_page
from twinlink.store.sqlite.history.queries import (
    data_extent,
    latest_values,
    select_series,
    signal_summaries,
)
from twinlink.store.sqlite.history.reader import HistoryReader
from twinlink.store.sqlite.history.writer import (
    MAX_SIGNALS_PER_STREAM,
    HistoryWriter,
    WriteFn,
)

__all__ = ["AggregateAnswer", "Downsampled", "SamplePage", "SqliteHistory"]


@dataclass(slots=True)
class AggregateAnswer:
    rows: list[dict[str, Any]]
    text_only: list[str] = field(default_factory=list)  # signals without a number in range


class SqliteHistory:
    def __init__(
        self,
        data_dir: Path,
        synchronous: str = "full",
        *,
        max_signals_per_stream: int = MAX_SIGNALS_PER_STREAM,
        faults: StorageFaults | None = None,
    ) -> None:
        self.path = data_dir / "history.db"
        self.writer = HistoryWriter(self.path, synchronous, max_signals_per_stream, faults)
        self.reader = HistoryReader(self.path)

    async def open(self) -> None:
        await self.writer.open()

    async def close(self) -> None:
        await self.reader.close()
        await self.writer.close()

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        return await self.writer.append(batch, device_id)

    async def write(self, fn: WriteFn) -> object:
        return await self.writer.write(fn)

    async def twin_ids(self) -> set[int]:
        """The twins that have series here."""
        rows = await self.reader.run(
            lambda conn: conn.execute("SELECT DISTINCT twin_id FROM series").fetchall()
        )
        return {int(r[0]) for r in rows}

    async def compact(self) -> Compacted:
        """Merge small blocks of the series that got them since the last call, one series
        per group commit (see compact.py)."""
        total = Compacted()
        for series_id in sorted(self.writer.take_small_blocks()):
            done: Compacted = await self.writer.write(
                partial(self.writer.compact, series_id=series_id)
            )
            total.blocks_before += done.blocks_before
            total.blocks_after += done.blocks_after
        return total

    # -- reads -------------------------------------------------------------------------

    async def streams(self, twin_id: int) -> list[dict[str, Any]]:
        """The twin's streams with their signals: kind, count, first and last time."""
        signals = await self.reader.run(partial(signal_summaries, twin_id=twin_id))
        streams: dict[str, dict[str, Any]] = {}
        for s in signals:
            name = s.pop("stream")
            stream = streams.setdefault(
                name, {"name": name, "count": 0, "first": s["first"], "last": s["last"]}
            )
            stream["count"] += s["count"]
            stream["first"] = min(stream["first"], s["first"])
            stream["last"] = max(stream["last"], s["last"])
            stream.setdefault("signals", []).append(s)
        return list(streams.values())

    async def latest(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> dict[str, dict[str, Any]]:
        """{signal: {time, value}} of the newest value of each signal."""
        return await self.reader.run(
            lambda conn: latest_values(conn, select_series(conn, twin_id, stream, signals))
        )

    async def extent(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> tuple[int, int] | None:
        """(first, last) time of the stored samples of these signals; None when none."""
        return await self.reader.run(
            lambda conn: data_extent(conn, select_series(conn, twin_id, stream, signals))
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
        """Up to `limit` rows {time, values} in time order; `next_key` continues the page."""
        return await self.reader.run(
            lambda conn: sample_page(
                conn, select_series(conn, twin_id, stream, signals), start, end, limit, after
            )
        )

    async def aggregate(
        self,
        twin_id: int,
        stream: str,
        signals: list[str] | None,
        start: int,
        end: int,
        width: int,
        fns: list[str],
    ) -> AggregateAnswer:
        """Rows {time: bucket start, values: {signal: {fn: value}}} for buckets of `width` ns
        aligned to the epoch; empty buckets are left out."""

        def run(conn: Any) -> AggregateAnswer:
            results = {
                s.signal: aggregate_series(conn, s, start, end, width)
                for s in select_series(conn, twin_id, stream, signals)
            }
            text = [name for name, r in results.items() if r.text_only]
            return AggregateAnswer(aggregate_rows(results, fns, width), text)

        return await self.reader.run(run)

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
        return await self.reader.run(
            lambda conn: {
                s.signal: downsample(conn, s, start, end, points, method)
                for s in select_series(conn, twin_id, stream, signals)
            }
        )

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
        first, so an unknown stream or signal fails before anything is sent."""
        series = await self.reader.run(lambda conn: select_series(conn, twin_id, stream, signals))
        pieces: AsyncIterator[bytes] = self.reader.stream(
            lambda conn: export_pieces(conn, series, start, end, fmt, time_format)
        )
        return [s.signal for s in series], pieces

    # -- deletes (through the writer's group commit, a chunk per commit) ---------------

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
        blocks = await self._repeat(
            partial(retention.delete_twin_blocks, twin_id=twin_id, chunk=chunk), chunk
        )

        def drop_series(conn: Any) -> int:
            count = retention.delete_twin_series(conn, twin_id)
            self.writer.forget_series(twin_id)
            return count

        await self.writer.write(drop_series)
        return blocks
