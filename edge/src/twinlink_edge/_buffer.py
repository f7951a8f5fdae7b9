"""Store-and-forward buffers: the sealed batches that have no ack yet, in `seq` order.

`MemoryBuffer` (the default) lives as long as the process; `DiskBuffer` keeps the batches and
the last sequence number in a SQLite file, so a restarted device resends what the server never
acknowledged and never reuses a sequence number. Neither is thread-safe on its own: the device
calls them under its lock."""

from __future__ import annotations

import os
import sqlite3
from abc import ABC, abstractmethod
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Buffer", "DiskBuffer", "MemoryBuffer", "StoredBatch"]


@dataclass(frozen=True)
class StoredBatch:
    seq: int
    stream: str
    count: int  # samples in the batch
    payload: str  # the `samples` message as JSON text, sent as it is


class Buffer(ABC):
    """The batches that have no ack yet. Subclasses keep `_counts` (seq -> samples) in seq
    order, so sizes and the oldest batch are known without touching storage."""

    def __init__(self) -> None:
        self._counts: OrderedDict[int, int] = OrderedDict()
        self.samples = 0

    @property
    def last_seq(self) -> int:
        """The highest sequence number this buffer ever held (0 when it knows none)."""
        return next(reversed(self._counts), 0)

    def seqs(self) -> list[int]:
        return list(self._counts)

    def first_seq(self) -> int | None:
        return next(iter(self._counts), None)

    def __len__(self) -> int:
        return len(self._counts)

    def __contains__(self, seq: object) -> bool:
        return seq in self._counts

    def put(self, batch: StoredBatch) -> None:
        if self._counts and batch.seq <= self.last_seq:
            raise ValueError(f"batch {batch.seq} is not after {self.last_seq}")
        self._store(batch)
        self._counts[batch.seq] = batch.count
        self.samples += batch.count

    def remove(self, seq: int) -> int | None:
        """Forget batch `seq`; returns its number of samples, None when it was not here."""
        count = self._counts.pop(seq, None)
        if count is not None:
            self._delete(seq)
            self.samples -= count
        return count

    def get(self, seq: int) -> StoredBatch | None:
        return self._load(seq) if seq in self._counts else None

    @abstractmethod
    def _store(self, batch: StoredBatch) -> None: ...

    @abstractmethod
    def _delete(self, seq: int) -> None: ...

    @abstractmethod
    def _load(self, seq: int) -> StoredBatch | None: ...

    def close(self) -> None:  # noqa: B027 - a buffer in memory has nothing to close
        pass


class MemoryBuffer(Buffer):
    """Batches in a dict: lost when the process ends."""

    def __init__(self) -> None:
        super().__init__()
        self._batches: dict[int, StoredBatch] = {}

    def _store(self, batch: StoredBatch) -> None:
        self._batches[batch.seq] = batch

    def _delete(self, seq: int) -> None:
        del self._batches[seq]

    def _load(self, seq: int) -> StoredBatch | None:
        return self._batches.get(seq)


_SCHEMA = """
CREATE TABLE IF NOT EXISTS batches (
    seq INTEGER PRIMARY KEY,
    stream TEXT NOT NULL,
    count INTEGER NOT NULL,
    payload TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value INTEGER NOT NULL);
"""


class DiskBuffer(Buffer):
    """Batches in a SQLite file `buffer.sqlite3` in `folder` (created when missing): they
    survive a restart of the process, and a batch is deleted when its ack arrives. One folder
    per device: the file holds no device identity.

    `synchronous` is SQLite's setting: `"NORMAL"` (the default) survives a crash of the
    process; `"FULL"` also survives a power cut, at the cost of a flush to the storage medium
    for every batch."""

    FILE = "buffer.sqlite3"

    def __init__(self, folder: str | os.PathLike[str], *, synchronous: str = "NORMAL"):
        super().__init__()
        if synchronous.upper() not in ("OFF", "NORMAL", "FULL", "EXTRA"):
            raise ValueError(f"unknown synchronous setting {synchronous!r}")
        self.path = Path(folder) / self.FILE
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._db = sqlite3.connect(str(self.path), check_same_thread=False, isolation_level=None)
        try:
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute(f"PRAGMA synchronous={synchronous.upper()}")
            self._db.executescript(_SCHEMA)
            for seq, count in self._db.execute("SELECT seq, count FROM batches ORDER BY seq"):
                self._counts[int(seq)] = int(count)
                self.samples += int(count)
            row = self._db.execute("SELECT value FROM meta WHERE key = 'last_seq'").fetchone()
        except BaseException:
            self._db.close()
            raise
        self._last_seq = max(int(row[0]) if row else 0, super().last_seq)

    @property
    def last_seq(self) -> int:
        return self._last_seq

    def _store(self, batch: StoredBatch) -> None:
        with self._db:  # one transaction: the batch and the counter go together
            self._db.execute("BEGIN")
            self._db.execute(
                "INSERT INTO batches (seq, stream, count, payload) VALUES (?, ?, ?, ?)",
                (batch.seq, batch.stream, batch.count, batch.payload),
            )
            self._db.execute(
                "INSERT OR REPLACE INTO meta (key, value) VALUES ('last_seq', ?)",
                (batch.seq,),
            )
        self._last_seq = batch.seq

    def _delete(self, seq: int) -> None:
        self._db.execute("DELETE FROM batches WHERE seq = ?", (seq,))

    def _load(self, seq: int) -> StoredBatch | None:
        row = self._db.execute(
            "SELECT stream, count, payload FROM batches WHERE seq = ?", (seq,)
        ).fetchone()
        return None if row is None else StoredBatch(seq, str(row[0]), int(row[1]), str(row[2]))

    def close(self) -> None:
        self._db.close()
