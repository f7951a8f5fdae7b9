"""Store-and-forward buffers: the sealed batches that have no ack yet, in `seq` order.

`MemoryBuffer` (the default) lives as long as the process; `DiskBuffer` keeps the batches and
the last sequence number in a SQLite file, so a restarted device resends what the server never
acknowledged and never reuses a sequence number. A `DiskBuffer` also holds samples not sealed
into a batch yet, one at a time, for a device with `durable=True`. Neither is thread-safe on
its own: the device calls them under its lock."""

from __future__ import annotations

import os
import sqlite3
from abc import ABC, abstractmethod
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path

from ._protocol import JsonObject, dumps, loads

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

    keeps_samples = False  # `hold` works: samples can wait for their batch in here too

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
        self.put_all([batch])

    def put_all(self, batches: list[StoredBatch], released: str | None = None) -> None:
        """Keep `batches` (in seq order). The samples held for stream `released` are in them:
        they are let go in the same step, so a crash leaves each sample in one place."""
        floor = self.last_seq if self._counts else None
        for batch in batches:
            if floor is not None and batch.seq <= floor:
                raise ValueError(f"batch {batch.seq} is not after {floor}")
            floor = batch.seq
        self._store(batches, released)
        for batch in batches:
            self._counts[batch.seq] = batch.count
            self.samples += batch.count

    def hold(self, stream: str, sample: JsonObject) -> None:
        """Keep a sample not sealed into a batch yet (`durable=True`)."""
        raise TypeError(
            f"a {type(self).__name__} cannot keep samples before their batch: "
            "durable=True needs a folder buffer"
        )

    def held(self) -> list[tuple[str, JsonObject]]:
        """The samples held and not released, in the order they came: (stream, sample)."""
        return []

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
    def _store(self, batches: list[StoredBatch], released: str | None) -> None: ...

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

    def _store(self, batches: list[StoredBatch], released: str | None) -> None:
        for batch in batches:
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
CREATE TABLE IF NOT EXISTS held (
    id INTEGER PRIMARY KEY,
    stream TEXT NOT NULL,
    sample TEXT NOT NULL
);
"""


class DiskBuffer(Buffer):
    """Batches in a SQLite file `buffer.sqlite3` in `folder` (created when missing): they
    survive a restart of the process, and a batch is deleted when its ack arrives. One folder
    per device: the file holds no device identity.

    `synchronous` is SQLite's setting: `"NORMAL"` (the default) survives a crash of the
    process; `"FULL"` also survives a power cut, at the cost of a flush to the storage medium
    for every batch (and, with `durable=True`, every sample)."""

    FILE = "buffer.sqlite3"
    keeps_samples = True

    def __init__(self, folder: str | os.PathLike[str], *, synchronous: str = "NORMAL"):
        super().__init__()
        if synchronous.upper() not in ("OFF", "NORMAL", "FULL", "EXTRA"):
            raise ValueError(f"unknown synchronous setting {synchronous!r}")
        self.path = Path(folder) / self.FILE
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._db = sqlite3.connect(str(self.path), check_same_thread=False, isolation_level=None)
        self._held: dict[str, int] = {}  # stream -> samples held in the file
        try:
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute(f"PRAGMA synchronous={synchronous.upper()}")
            self._db.executescript(_SCHEMA)
            for seq, count in self._db.execute("SELECT seq, count FROM batches ORDER BY seq"):
                self._counts[int(seq)] = int(count)
                self.samples += int(count)
            row = self._db.execute("SELECT value FROM meta WHERE key = 'last_seq'").fetchone()
            for stream, count in self._db.execute("SELECT stream, count(*) FROM held GROUP BY 1"):
                self._held[str(stream)] = int(count)
        except BaseException:
            self._db.close()
            raise
        self._last_seq = max(int(row[0]) if row else 0, super().last_seq)

    @property
    def last_seq(self) -> int:
        return self._last_seq

    def _store(self, batches: list[StoredBatch], released: str | None) -> None:
        if not batches:
            return
        release = released if released in self._held else None
        with self._db:  # one transaction: the batches, the counter and the held samples
            self._db.execute("BEGIN")
            self._db.executemany(
                "INSERT INTO batches (seq, stream, count, payload) VALUES (?, ?, ?, ?)",
                [(b.seq, b.stream, b.count, b.payload) for b in batches],
            )
            self._db.execute(
                "INSERT OR REPLACE INTO meta (key, value) VALUES ('last_seq', ?)",
                (batches[-1].seq,),
            )
            if release is not None:
                self._db.execute("DELETE FROM held WHERE stream = ?", (release,))
        self._last_seq = batches[-1].seq
        if release is not None:
            del self._held[release]

    def hold(self, stream: str, sample: JsonObject) -> None:
        # One transaction a sample: in SQLite's file (its WAL) when this returns.
        self._db.execute("INSERT INTO held (stream, sample) VALUES (?, ?)", (stream, dumps(sample)))
        self._held[stream] = self._held.get(stream, 0) + 1

    def held(self) -> list[tuple[str, JsonObject]]:
        rows = self._db.execute("SELECT stream, sample FROM held ORDER BY id")
        return [(str(stream), loads(text)) for stream, text in rows]

    def _delete(self, seq: int) -> None:
        self._db.execute("DELETE FROM batches WHERE seq = ?", (seq,))

    def _load(self, seq: int) -> StoredBatch | None:
        row = self._db.execute(
            "SELECT stream, count, payload FROM batches WHERE seq = ?", (seq,)
        ).fetchone()
        return None if row is None else StoredBatch(seq, str(row[0]), int(row[1]), str(row[2]))

    def close(self) -> None:
        self._db.close()
