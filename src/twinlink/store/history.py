"""The interface of time-series storage (SQLite now, PostgreSQL later).

Three sides, so each user asks for what it needs: ingest and processors write
(`HistoryWriterStore`), the history API reads (`HistoryReadStore`), maintenance keeps the
store tidy (`HistoryUpkeep`); a backend implements all three (`HistoryStore`). `app.py` picks
the implementation. Times are ns since the epoch; `start` and `end` are inclusive, and
`domain.history.MIN_TIME`/`MAX_TIME` stand for "no bound". Reads raise NotFoundError for an
unknown stream or signal (naming those that exist) and a `ReadBudgetError` when they would
cost more than the store allows.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any, Protocol

from twinlink.domain.history import Aggregated, Compaction, Downsampled, SamplePage
from twinlink.domain.samples import SampleBatch


class HistoryWriterStore(Protocol):
    """The write side, used by ingest and processors."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        """Store `batch` durably and return True; False when this device's `seq` was already
        stored (nothing is written again). Returns only once the batch is durable."""
        ...

    async def unpublished(self, device_id: int, seq: int) -> bool:
        """Whether this device's `seq`, stored (`append` said False), may not have reached
        the bus: its publish failed after the commit, or its node stopped between the two.
        The resend that asks publishes it then (docs/decisions/0013). Always False where the
        bus cannot fail (embedded)."""
        ...

    def published(self, device_id: int, seq: int) -> None:
        """Note that the device's batch `seq` is on the bus. May be kept lazily: a note lost
        costs a duplicate on the bus when the batch is sent again, never a lost sample."""
        ...


class HistoryReadStore(Protocol):
    """The read side, used by the history API and live clients' first values. Every read
    sees every batch whose `append` has returned."""

    async def streams(self, twin_id: int) -> list[dict[str, Any]]:
        """The twin's streams: {name, samples (rows; None when too many to count), values,
        count (= values, an older name), first, last, signals: [{name, kind, values, count,
        first, last}]}."""
        ...

    async def latest(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> dict[str, dict[str, Any]]:
        """{signal: {time, value}} of the newest value of each signal."""
        ...

    async def extent(
        self, twin_id: int, stream: str, signals: list[str] | None
    ) -> tuple[int, int] | None:
        """(first, last) time of the stored samples of these signals; None when none."""
        ...

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
        """Up to `limit` rows in time order, the signals of one batch joined in a row;
        samples of equal times keep their order of arrival. `after` is the `next_key` of
        the page before (the cursor)."""
        ...

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
        """Per bucket of `width` ns aligned to the epoch, each function of `fns`
        (domain.history.FUNCTIONS) of each numeric signal; empty buckets are left out, sums
        of integers are exact."""
        ...

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
        """Per signal, at most `points` samples that keep the shape (`method` of
        domain.history.METHODS)."""
        ...

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
        """The signal names, and the range as `fmt` text (domain.history.FORMATS) in pieces.
        An unknown stream or signal fails before the first piece; the pieces stop
        (ReadBudgetError) when the export runs over its time."""
        ...


class HistoryUpkeep(Protocol):
    """Retention, deleted twins and background compaction (history/maintenance.py)."""

    async def twin_ids(self) -> set[int]:
        """The twins that have history here."""
        ...

    async def compact(self) -> Compaction:
        """Merge what many small batches left behind into fewer, larger pieces, without
        holding up ingest for long; reads cannot tell the difference."""
        ...

    async def delete_before(self, cutoff_ns: int) -> int:
        """Delete the samples older than the cutoff (a store may keep some a little longer,
        to delete in whole pieces); the number of pieces deleted."""
        ...

    async def forget_ingested_before(self, cutoff_ns: int) -> int:
        """Forget which batches were stored before the cutoff (the record that makes a
        resent batch a duplicate); the number forgotten."""
        ...

    async def delete_twin(self, twin_id: int) -> int:
        """Delete all history of a twin; the number of pieces deleted."""
        ...

    async def reclaim_space(self) -> None:
        """After deletions: hand the space they freed back to the disk where the store can."""
        ...


class HistoryStore(HistoryWriterStore, HistoryReadStore, HistoryUpkeep, Protocol):
    """Everything a history backend provides."""
