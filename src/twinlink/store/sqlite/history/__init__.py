"""Time series in an embedded SQLite file (`history.db` in the data dir)."""

from __future__ import annotations

from pathlib import Path

from twinlink.domain.samples import SampleBatch
from twinlink.store.sqlite.history.writer import HistoryWriter, WriteFn


class SqliteHistory:
    def __init__(self, data_dir: Path, synchronous: str = "full") -> None:
        self.path = data_dir / "history.db"
        self.writer = HistoryWriter(self.path, synchronous)

    async def open(self) -> None:
        await self.writer.open()

    async def close(self) -> None:
        await self.writer.close()

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        return await self.writer.append(batch, device_id)

    async def write(self, fn: WriteFn) -> object:
        return await self.writer.write(fn)
