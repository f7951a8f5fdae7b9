"""A twin's streams for /streams: per signal its values, per stream its samples and values.

A signal's values are the sum of its blocks' counts. A stream's samples are the rows that
/samples and /export give: joined on (time, occurrence), a time counts as many times as the
signal with the most samples at it. When every signal of a stream holds the same multiset of
times (they were sent together, the common case), the rows are one signal's count; the blocks'
`times_hash` columns tell that from one SQL statement. Otherwise the times of one signal per
distinct multiset are read and joined (as the export does, without the values), up to
`COUNT_LIMIT` times; beyond that `samples` is None (unknown) rather than slow.
"""

from __future__ import annotations

import sqlite3
from typing import Any

import numpy as np

from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.codec import HASH_BITS, TIME_DTYPE
from twinlink.store.sqlite.history.queries import Series, kind_name
from twinlink.store.sqlite.history.scan import SeriesSet, time_pages

COUNT_LIMIT = 5_000_000  # times read at most to count the samples of one stream
_HALF = 31


def stream_summaries(
    conn: sqlite3.Connection, twin_id: int, budget: ReadBudget
) -> list[dict[str, Any]]:
    """Per stream: name, samples, values, first and last time, and its signals (name, kind,
    values, first, last). `count` is the old name of `values`, kept for older clients."""
    rows = conn.execute(
        "SELECT s.stream, s.signal, s.id, s.max_span_ns, SUM(b.n), MIN(b.t0), MAX(b.t1), "
        f"GROUP_CONCAT(DISTINCT b.kind), SUM(b.times_hash >> {_HALF}), "
        f"SUM(b.times_hash & {(1 << _HALF) - 1}), COUNT(b.times_hash) = COUNT(*) "
        "FROM series s JOIN blocks b ON b.series_id = s.id WHERE s.twin_id = ? "
        "GROUP BY s.id ORDER BY s.stream, s.signal",
        (twin_id,),
    ).fetchall()
    streams: dict[str, dict[str, Any]] = {}
    multisets: dict[str, dict[tuple[int, int] | int, Series]] = {}
    for name, signal, sid, span, values, first, last, kinds, high, low, hashed in rows:
        stream = streams.get(name)
        if stream is None:
            stream = streams[name] = {
                "name": name, "samples": 0, "values": 0, "count": 0, "first": first,
                "last": last, "signals": [],
            }  # fmt: skip
        stream["values"] += values
        stream["first"], stream["last"] = min(stream["first"], first), max(stream["last"], last)
        stream["signals"].append(
            {"name": signal, "kind": kind_name(set(kinds.split(","))), "values": values,
             "count": values, "first": first, "last": last}
        )  # fmt: skip
        # Equal times (as multisets) give equal keys; a signal with blocks written before
        # times_hash is a key of its own.
        key = (values, ((high << _HALF) + low) & ((1 << HASH_BITS) - 1)) if hashed else sid
        multisets.setdefault(name, {}).setdefault(key, Series(sid, name, signal, span))
    for name, stream in streams.items():
        stream["count"] = stream["values"]
        distinct = multisets[name]
        only = next(iter(distinct))
        if len(distinct) == 1 and isinstance(only, tuple):
            stream["samples"] = only[0]
        else:
            stream["samples"] = row_count(conn, list(distinct.values()), budget)
    return list(streams.values())


def row_count(conn: sqlite3.Connection, series: list[Series], budget: ReadBudget) -> int | None:
    """The rows the samples of `series` join into; None when that means reading more than
    COUNT_LIMIT times."""
    if conn.execute(
        "SELECT COALESCE(SUM(n), 0) > ? FROM blocks WHERE series_id IN "
        "(SELECT value FROM json_each(?))",
        (COUNT_LIMIT, SeriesSet.of(series).ids_json),
    ).fetchone()[0]:
        return None
    rows = 0
    held_t = np.empty(0, dtype=TIME_DTYPE)
    held_s = np.empty(0, dtype=np.intp)
    pages = time_pages(conn, SeriesSet.of(series), MIN_TIME, MAX_TIME, budget, False)
    for page in pages:
        sizes = [len(t) // 8 for t in page.times]
        times = np.concatenate([held_t, np.frombuffer(b"".join(page.times), dtype=TIME_DTYPE)])
        owner = np.concatenate([held_s, np.repeat(page.series, sizes)])
        final = times < (MAX_TIME if page.frontier is None else page.frontier)
        final |= page.frontier is None
        rows += _joined(times[final], owner[final])
        held_t, held_s = times[~final], owner[~final]
    return rows + _joined(held_t, held_s)


def _joined(times: np.ndarray[Any, np.dtype[np.int64]], owner: np.ndarray[Any, Any]) -> int:
    """The rows of samples joined on (time, occurrence): per time, the most samples one
    signal has at it."""
    if times.size == 0:
        return 0
    order = np.lexsort((times, owner))
    t, o = times[order], owner[order]
    new = np.r_[True, (t[1:] != t[:-1]) | (o[1:] != o[:-1])]
    index = np.arange(t.size)
    occurrence = index - np.maximum.accumulate(np.where(new, index, 0))
    pairs = np.unique(np.stack([t, occurrence], axis=1), axis=0)
    return int(pairs.shape[0])
