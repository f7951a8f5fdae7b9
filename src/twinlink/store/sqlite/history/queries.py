"""The SQL of the read side: which series a query is about, and which of their blocks.

Every block query bounds its index scan the same way: a block that holds samples in
[start, end] begins no earlier than `start - max_span_ns` of its series, so
`t0 BETWEEN start - max_span AND end AND t1 >= start` walks `blocks_by_series_time` over
the range and nothing more.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import orjson

from twinlink.domain.errors import NotFoundError

MIN_TIME = -(2**63)
MAX_TIME = 2**63 - 1
_KIND_NAMES = {"i": "integer", "f": "number", "b": "bool", "j": "string"}
_MAX_PAGE_BLOCKS = 256
_PAGE_SAMPLES = 65_536
_IN_CHUNK = 500


@dataclass(frozen=True, slots=True)
class Series:
    id: int
    stream: str
    signal: str
    max_span: int

    def scan(self, start: int, end: int) -> tuple[int, int, int, int]:
        """(series id, lowest t0, highest t0, lowest t1) of blocks that may hold samples in
        [start, end]."""
        return (self.id, max(MIN_TIME, start - self.max_span), end, start)


BLOCKS_IN_RANGE = "series_id = ? AND t0 BETWEEN ? AND ? AND t1 >= ?"


def kind_name(kinds: set[str]) -> str:
    """The kind of a signal from the kinds of its blocks: integer, number, bool, string (text,
    or a batch that mixed text and numbers) or mixed."""
    if len(kinds) == 1:
        return _KIND_NAMES[next(iter(kinds))]
    return "number" if kinds <= {"i", "f"} else "mixed"


def select_series(
    conn: sqlite3.Connection, twin_id: int, stream: str, signals: list[str] | None
) -> list[Series]:
    """The series of `signals` (every signal when None) in one stream, in the order asked.
    NotFoundError names what exists when the stream or a signal does not."""
    rows = conn.execute(
        "SELECT id, stream, signal, max_span_ns FROM series WHERE twin_id = ? AND stream = ? "
        "ORDER BY signal",
        (twin_id, stream),
    ).fetchall()
    known = {row[2]: Series(*row) for row in rows}
    if not known:
        streams = [r[0] for r in conn.execute(STREAM_NAMES, (twin_id,))]
        have = f"its streams: {', '.join(streams)}" if streams else "it has no history yet"
        raise NotFoundError(f"no stream {stream!r} in this twin's history ({have})")
    if signals is None:
        return list(known.values())
    missing = [s for s in signals if s not in known]
    if missing:
        raise NotFoundError(
            f"stream {stream!r} has no signal {', '.join(map(repr, missing))} "
            f"(its signals: {', '.join(known)})"
        )
    return [known[s] for s in dict.fromkeys(signals)]


STREAM_NAMES = "SELECT DISTINCT stream FROM series WHERE twin_id = ? ORDER BY stream"


def signal_summaries(conn: sqlite3.Connection, twin_id: int) -> list[dict[str, Any]]:
    """Per signal with stored samples: stream, name, kind, count, first and last time."""
    rows = conn.execute(
        "SELECT s.stream, s.signal, SUM(b.n), MIN(b.t0), MAX(b.t1), GROUP_CONCAT(DISTINCT b.kind)"
        " FROM series s JOIN blocks b ON b.series_id = s.id WHERE s.twin_id = ?"
        " GROUP BY s.id ORDER BY s.stream, s.signal",
        (twin_id,),
    )
    return [
        {
            "stream": stream,
            "name": signal,
            "kind": kind_name(set(kinds.split(","))),
            "count": count,
            "first": first,
            "last": last,
        }
        for stream, signal, count, first, last, kinds in rows
    ]


def latest_values(conn: sqlite3.Connection, series: list[Series]) -> dict[str, dict[str, Any]]:
    """The newest value of each series that has one: {signal: {time, value}}."""
    by_id = {s.id: s.signal for s in series}
    found: dict[int, tuple[int, str]] = {}
    ids = list(by_id)
    for i in range(0, len(ids), _IN_CHUNK):
        part = ids[i : i + _IN_CHUNK]
        marks = ",".join("?" * len(part))
        for sid, t, value in conn.execute(
            f"SELECT series_id, t, value FROM latest WHERE series_id IN ({marks})", part
        ):
            found[sid] = (t, value)
    return {
        by_id[sid]: {"time": found[sid][0], "value": orjson.loads(found[sid][1])}
        for sid in ids
        if sid in found
    }


def data_extent(conn: sqlite3.Connection, series: list[Series]) -> tuple[int, int] | None:
    """The first block start and the last block end over `series`; None when all are empty."""
    first, last = MAX_TIME, MIN_TIME
    for s in series:
        lo = conn.execute("SELECT MIN(t0) FROM blocks WHERE series_id = ?", (s.id,)).fetchone()[0]
        if lo is None:
            continue
        # The block with the largest t1 starts within max_span of the largest t0.
        hi = conn.execute(
            "SELECT MAX(t1) FROM blocks WHERE series_id = ? AND t0 >= "
            "(SELECT MAX(t0) FROM blocks WHERE series_id = ?) - ?",
            (s.id, s.id, s.max_span),
        ).fetchone()[0]
        first, last = min(first, lo), max(last, hi)
    return None if first > last else (first, last)


def count_blocks(
    conn: sqlite3.Connection, s: Series, start: int, end: int, up_to: int
) -> tuple[int, int]:
    """(blocks, samples) of the blocks that touch [start, end], counting at most `up_to + 1`
    blocks (enough to tell "more than up_to" without walking a long range). Samples counts
    whole blocks, so it is more than the range holds when blocks stick out of it."""
    row = conn.execute(
        f"SELECT COUNT(*), COALESCE(SUM(n), 0) FROM (SELECT n FROM blocks "
        f"WHERE {BLOCKS_IN_RANGE} LIMIT ?)",
        (*s.scan(start, end), up_to + 1),
    ).fetchone()
    return int(row[0]), int(row[1])


def holds_numbers(conn: sqlite3.Connection, s: Series, start: int, end: int) -> bool | None:
    """Whether a signal has numbers in [start, end]: True when one of its blocks there is
    numeric (integer, number or bool), False when all of them hold JSON (text), None when it
    has no block there."""
    scan = s.scan(start, end)
    numeric = f"SELECT EXISTS (SELECT 1 FROM blocks WHERE {BLOCKS_IN_RANGE} AND kind != 'j')"
    if conn.execute(numeric, scan).fetchone()[0]:
        return True
    some = f"SELECT EXISTS (SELECT 1 FROM blocks WHERE {BLOCKS_IN_RANGE})"
    return False if conn.execute(some, scan).fetchone()[0] else None


def block_pages(
    conn: sqlite3.Connection, s: Series, start: int, end: int
) -> Iterator[list[tuple[int, int, str, bytes, bytes]]]:
    """(rowid, t0, kind, times, vals) of the blocks touching [start, end], by (t0, rowid), a
    page at a time. Each page is its own short read, so a long export holds no snapshot."""
    after: tuple[int, int] = (MIN_TIME, -1)
    limit = 4
    while True:
        rows = conn.execute(
            f"SELECT rowid, t0, kind, times, vals, n FROM blocks WHERE {BLOCKS_IN_RANGE} "
            "AND (t0, rowid) > (?, ?) ORDER BY t0, rowid LIMIT ?",
            (*s.scan(start, end), *after, limit),
        ).fetchall()
        if not rows:
            return
        yield [row[:5] for row in rows]
        if len(rows) < limit:
            return
        after = (rows[-1][1], rows[-1][0])
        mean_n = max(1, sum(row[5] for row in rows) // len(rows))
        limit = max(1, min(_MAX_PAGE_BLOCKS, limit * 2, _PAGE_SAMPLES // mean_n))


def blocks_by_rowid(
    conn: sqlite3.Connection, rowids: list[int]
) -> dict[int, tuple[str, bytes, bytes]]:
    """{rowid: (kind, times, vals)} of the given blocks."""
    found: dict[int, tuple[str, bytes, bytes]] = {}
    for i in range(0, len(rowids), _IN_CHUNK):
        part = rowids[i : i + _IN_CHUNK]
        marks = ",".join("?" * len(part))
        for rowid, kind, times, vals in conn.execute(
            f"SELECT rowid, kind, times, vals FROM blocks WHERE rowid IN ({marks})", part
        ):
            found[rowid] = (kind, times, vals)
    return found
