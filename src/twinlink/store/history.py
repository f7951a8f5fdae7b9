"""The interface of time-series storage (SQLite now, PostgreSQL later)."""

from __future__ import annotations

from typing import Protocol

from twinlink.domain.samples import SampleBatch


class HistoryWriterStore(Protocol):
    """The write side, used by ingest and processors."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        """Store `batch` durably and return True; False when this device's `seq` was already
        stored (nothing is written again). Returns only once the batch is durable."""
        ...
