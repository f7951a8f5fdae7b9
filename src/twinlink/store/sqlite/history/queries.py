"""The SQL of the read side: which series a query is about, and which of their blocks.

Every block query bounds its index scan the same way: a block that holds samples in
[start, end] begins no earlier than `start - max_span_ns` of its series, so
`t0 BETWEEN start - max_span AND end AND t1 >= start` walks `blocks_by_series_time` over
the range and nothing more.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any

import orjson

from twinlink.domain.errors import NotFoundError
from twinlink.domain.history import MIN_TIME

_KIND_NAMES = {"i": "integer", "f": "number", "b": "bool", "j": "string"}
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
# Many series in one statement: their ids as one JSON array parameter (scan.py).
IN_SERIES = "series_id IN (SELECT value FROM json_each(?))"


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
            f"stream {stream!r} has no signal {_some(list(map(repr, missing)))} "
            f"(its signals: {_some(list(known))})"
        )
    return [known[s] for s in dict.fromkeys(signals)]


def _some(names: list[str], most: int = 20) -> str:
    """Names for a message: a stream may have thousands of signals, a message shows 20."""
    if len(names) <= most:
        return ", ".join(names)
    return f"{', '.join(names[:most])} and {len(names) - most} more"


STREAM_NAMES = "SELECT DISTINCT stream FROM series WHERE twin_id = ? ORDER BY stream"


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
    """The first block start and the last block end over `series`; None when all are empty.
    Two statements whatever the number of series (an index seek or two per series)."""
    ids = orjson.dumps([s.id for s in series]).decode()
    widest = max((s.max_span for s in series), default=0)
    first = conn.execute(
        "SELECT MIN((SELECT MIN(t0) FROM blocks WHERE series_id = j.value)) FROM json_each(?) j",
        (ids,),
    ).fetchone()[0]
    if first is None:
        return None
    # A series' block with the largest t1 starts within max_span of its largest t0.
    last = conn.execute(
        "SELECT MAX((SELECT MAX(t1) FROM blocks WHERE series_id = j.value AND t0 >= "
        "(SELECT MAX(t0) FROM blocks WHERE series_id = j.value) - ?)) FROM json_each(?) j",
        (widest, ids),
    ).fetchone()[0]
    return int(first), int(last)


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
