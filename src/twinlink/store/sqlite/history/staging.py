"""Small batches staged, then moved into column blocks in bulk.

A device that sends one sample at a time would cost a block row (with its index entries and
summary) per signal per sample, and compaction would rewrite each of them later: 2 000 such
devices at 2 samples/s are 16 000 block rows a second. A batch of fewer than `STAGE_BELOW`
samples is instead one row of `staged` in the same group commit (so it is as durable, and
its `seq` as deduplicated, as any other). The writer moves staged rows into blocks, a block
per signal of all that signal's staged samples:
- when `FLUSH_ROWS` rows are staged, or the oldest has waited `FLUSH_AFTER_S`, or one twin
  has `TWIN_FLUSH_ROWS` (a read of it then never waits for many);
- before any read of the twin (`SqliteHistory` settles the twin first), so readers never
  see this table and every read sees every acknowledged sample;
- at close, and at open for rows a crash left behind.
Samples keep their arrival order among equal times, as blocks written batch by batch do,
and batches of a signal are only joined when their values are of one kind (integers, numbers,
bools, or text and mixed values, `codec.kind_of`), so a block holds what the batches' own
blocks would have held: an integer stays an integer, and a batch with text stays text; and
when they lie within `compact.MAX_SPAN_NS` of each other, as compaction joins blocks (an old
batch sent late does not keep new samples from retention, which deletes whole blocks).
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import orjson

from twinlink.domain.samples import Value
from twinlink.store.sqlite.history.codec import kind_of
from twinlink.store.sqlite.history.compact import MAX_SPAN_NS

STAGE_BELOW = 8  # samples: smaller batches are staged (codec.SMALL_BLOCK)
# Moved rarely, so a signal's block holds many samples (a 2 Hz device's 60 after 30 s) and
# compaction has little left to merge; moved 500 rows a group commit (a few ms of work) with
# a gap between such commits, so acks hardly wait for it.
FLUSH_ROWS = 100_000  # staged rows (about 20 MB) that make the writer move them
FLUSH_AFTER_S = 30.0  # the longest a staged row waits when nothing else moves it
TWIN_FLUSH_ROWS = 5_000  # one twin's staged rows that make the writer move them
FLUSH_ROUND_ROWS = 500  # rows moved per group commit (about: whole twins at a time)
FLUSH_GAP_S = 0.02  # between two such commits, for the others (a drain takes seconds)

INSERT_STAGED = "INSERT INTO staged (twin_id, stream, body) VALUES (?, ?, ?)"

Column = tuple[int, str, list[int], list[Value]]  # series id, signal, times, values


def staged_row(twin_id: int, stream: str, columns: list[Column]) -> tuple[int, str, bytes]:
    """The parameters of INSERT_STAGED for one batch."""
    return (twin_id, stream, orjson.dumps(columns))


@dataclass(slots=True)
class Run:
    """Samples of one series from consecutive staged batches of one kind of value."""

    series_id: int
    key: tuple[int, str, str]  # twin id, stream, signal
    kind: str
    times: list[int]
    values: list[Value]
    first: int  # the earliest and the latest of `times`
    last: int


@dataclass(slots=True)
class Gathered:
    """Staged rows read for moving: per series its runs of samples, in arrival order."""

    rowids: list[int] = field(default_factory=list)
    runs: list[Run] = field(default_factory=list)
    twins: dict[int, int] = field(default_factory=dict)  # twin id -> rows read
    _last: dict[int, Run] = field(default_factory=dict)  # series id -> its latest run

    def add(self, rowid: int, twin_id: int, stream: str, body: bytes) -> None:
        self.rowids.append(rowid)
        self.twins[twin_id] = self.twins.get(twin_id, 0) + 1
        for series_id, signal, times, values in orjson.loads(body):
            kind = kind_of(values)
            first, last = min(times), max(times)
            run = self._last.get(series_id)
            if (
                run is not None
                and run.kind == kind
                and max(last, run.last) - min(first, run.first) <= MAX_SPAN_NS
            ):
                run.times.extend(times)
                run.values.extend(values)
                run.first, run.last = min(first, run.first), max(last, run.last)
                continue
            run = Run(series_id, (twin_id, stream, signal), kind, times, values, first, last)
            self._last[series_id] = run
            self.runs.append(run)


def gather(conn: sqlite3.Connection, twins: list[int], limit: int) -> Gathered:
    """The staged rows of `twins`, the oldest first: all of them (a twin's rows are moved
    together, so each of its signals makes one block), or the oldest `limit` of one twin."""
    if len(twins) == 1:
        rows = conn.execute(
            "SELECT id, twin_id, stream, body FROM staged WHERE twin_id = ? ORDER BY id LIMIT ?",
            (twins[0], limit),
        )
    else:
        marks = ",".join("?" * len(twins))
        rows = conn.execute(
            f"SELECT id, twin_id, stream, body FROM staged WHERE twin_id IN ({marks}) ORDER BY id",
            twins,
        )
    out = Gathered()
    for rowid, twin, stream, body in rows:
        out.add(rowid, twin, stream, body)
    return out


def delete_rows(conn: sqlite3.Connection, rowids: list[int]) -> None:
    for part in _chunks(rowids, 500):
        conn.execute(f"DELETE FROM staged WHERE id IN ({','.join('?' * len(part))})", part)


def counts(conn: sqlite3.Connection) -> dict[int, int]:
    """Staged rows per twin (at open: rows a crash left)."""
    return dict(conn.execute("SELECT twin_id, COUNT(*) FROM staged GROUP BY twin_id"))


def delete_twin(conn: sqlite3.Connection, twin_id: int) -> int:
    return conn.execute("DELETE FROM staged WHERE twin_id = ?", (twin_id,)).rowcount


def _chunks(items: list[Any], size: int) -> Iterator[list[Any]]:
    for i in range(0, len(items), size):
        yield items[i : i + size]
