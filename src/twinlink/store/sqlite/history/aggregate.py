"""Aggregation over fixed time buckets, from block summaries where it can.

A block that lies inside [start, end] and inside one bucket adds its stored summary (count,
sum, min, max, first, last) to that bucket; SQLite groups those summaries itself, so they cost
an index walk and no decoding. Only blocks that straddle a bucket edge or the range ends (and
blocks of mixed JSON values) are decoded, sample by sample.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.columns import Floats, Times, numeric_column
from twinlink.store.sqlite.history.queries import BLOCKS_IN_RANGE, Series, holds_numbers

FUNCTIONS = ("avg", "min", "max", "count", "first", "last", "sum")
Buckets = npt.NDArray[np.int64]

# A block wholly inside [start, end] and inside one bucket: bucket(t) = (t - origin) / width.
INSIDE_ONE_BUCKET = "kind != 'j' AND t0 >= ? AND t1 <= ? AND (t0 - ?) / ? = (t1 - ?) / ?"


def inside_args(start: int, end: int, origin: int, width: int) -> tuple[int, ...]:
    return (start, end, origin, width, origin, width)


@dataclass(slots=True)
class Partials:
    """Partial aggregates, one per (bucket, source); `reduce` makes them one per bucket."""

    bucket: Buckets
    count: npt.NDArray[np.int64]
    total: Floats
    low: Floats
    high: Floats
    first_t: Times
    first_v: Floats
    last_t: Times
    last_v: Floats

    def __len__(self) -> int:
        return int(self.bucket.size)

    @classmethod
    def empty(cls) -> Partials:
        ints, floats = np.empty(0, dtype=np.int64), np.empty(0, dtype=np.float64)
        return cls(ints, ints, floats, floats, floats, ints, floats, ints, floats)

    @classmethod
    def concat(cls, parts: list[Partials]) -> Partials:
        names = cls.__slots__
        return cls(*(np.concatenate([getattr(p, n) for p in parts]) for n in names))

    def reduce(self) -> Partials:
        if len(self) == 0:
            return self
        order = np.lexsort((self.first_t, self.bucket))
        b = self.bucket[order]
        starts = np.flatnonzero(np.r_[True, b[1:] != b[:-1]])
        by_last = np.lexsort((self.last_t, self.bucket))
        ends = np.r_[starts[1:], b.size] - 1
        return Partials(
            bucket=b[starts],
            count=np.add.reduceat(self.count[order], starts),
            total=np.add.reduceat(self.total[order], starts),
            low=np.minimum.reduceat(self.low[order], starts),
            high=np.maximum.reduceat(self.high[order], starts),
            first_t=self.first_t[order][starts],
            first_v=self.first_v[order][starts],
            last_t=self.last_t[by_last][ends],
            last_v=self.last_v[by_last][ends],
        )

    def values(self, fn: str) -> list[Any]:
        column = {
            "avg": self.total / np.maximum(self.count, 1),
            "min": self.low,
            "max": self.high,
            "count": self.count,
            "first": self.first_v,
            "last": self.last_v,
            "sum": self.total,
        }[fn]
        return column.tolist()  # type: ignore[no-any-return]


def sample_partials(times: Times, values: Floats, origin: int, width: int) -> Partials:
    """Per-bucket partials of samples sorted by time (each bucket is one contiguous run)."""
    if times.size == 0:
        return Partials.empty()
    b = (times - origin) // width
    starts = np.flatnonzero(np.r_[True, b[1:] != b[:-1]])
    ends = np.r_[starts[1:], b.size] - 1
    return Partials(
        bucket=b[starts],
        count=np.diff(np.r_[starts, b.size]).astype(np.int64),
        total=np.add.reduceat(values, starts),
        low=np.minimum.reduceat(values, starts),
        high=np.maximum.reduceat(values, starts),
        first_t=times[starts],
        first_v=values[starts],
        last_t=times[ends],
        last_v=values[ends],
    )


def _summary_partials(
    conn: sqlite3.Connection, s: Series, start: int, end: int, origin: int, width: int
) -> Partials:
    where = f"{BLOCKS_IN_RANGE} AND {INSIDE_ONE_BUCKET}"
    args = (origin, width, *s.scan(start, end), *inside_args(start, end, origin, width))
    sums = conn.execute(
        f"SELECT (t0 - ?) / ? AS b, SUM(n), SUM(vsum), MIN(vmin), MAX(vmax) FROM blocks "
        f"WHERE {where} GROUP BY b ORDER BY b",
        args,
    ).fetchall()
    if not sums:
        return Partials.empty()
    # With one min() or max() in a query, SQLite takes the other columns from that row.
    firsts = conn.execute(
        f"SELECT (t0 - ?) / ? AS b, MIN(t0), first_v FROM blocks WHERE {where} "
        "GROUP BY b ORDER BY b",
        args,
    ).fetchall()
    lasts = conn.execute(
        f"SELECT (t0 - ?) / ? AS b, MAX(t1), last_v FROM blocks WHERE {where} "
        "GROUP BY b ORDER BY b",
        args,
    ).fetchall()
    b, count, total, low, high = (np.asarray(c) for c in zip(*sums, strict=True))
    _, first_t, first_v = (np.asarray(c) for c in zip(*firsts, strict=True))
    _, last_t, last_v = (np.asarray(c) for c in zip(*lasts, strict=True))
    return Partials(
        bucket=b.astype(np.int64),
        count=count.astype(np.int64),
        total=total.astype(np.float64),
        low=low.astype(np.float64),
        high=high.astype(np.float64),
        first_t=first_t.astype(np.int64),
        first_v=first_v.astype(np.float64),
        last_t=last_t.astype(np.int64),
        last_v=last_v.astype(np.float64),
    )


def straddling_samples(
    conn: sqlite3.Connection, s: Series, start: int, end: int, origin: int, width: int
) -> tuple[Times, Floats]:
    """The numeric samples in [start, end] of the blocks that are not inside one bucket."""
    blocks = conn.execute(
        f"SELECT t0, t1, kind, times, vals FROM blocks WHERE {BLOCKS_IN_RANGE} "
        f"AND NOT ({INSIDE_ONE_BUCKET}) ORDER BY t0, rowid",
        (*s.scan(start, end), *inside_args(start, end, origin, width)),
    ).fetchall()
    return numeric_column(blocks, start, end)


@dataclass(slots=True)
class SignalBuckets:
    partials: Partials
    text_only: bool  # the signal has blocks in range, and none of them is numeric


def aggregate_series(
    conn: sqlite3.Connection, s: Series, start: int, end: int, width: int, origin: int = 0
) -> SignalBuckets:
    """Per-bucket aggregates of one signal over [start, end]; buckets are
    [origin + k * width, origin + (k + 1) * width)."""
    numbers = holds_numbers(conn, s, start, end)
    if not numbers:
        return SignalBuckets(Partials.empty(), text_only=numbers is False)
    summary = _summary_partials(conn, s, start, end, origin, width)
    times, values = straddling_samples(conn, s, start, end, origin, width)
    samples = sample_partials(times, values, origin, width)
    return SignalBuckets(Partials.concat([summary, samples]).reduce(), text_only=False)


def aggregate_rows(
    results: dict[str, SignalBuckets], fns: list[str], width: int, origin: int = 0
) -> list[dict[str, Any]]:
    """Rows joined on the bucket start: {time, values: {signal: {fn: value}}}."""
    rows: dict[int, dict[str, Any]] = {}
    for name, result in results.items():
        p = result.partials
        columns = [p.values(fn) for fn in fns]
        for i, bucket in enumerate(p.bucket.tolist()):
            row = rows.setdefault(bucket, {"time": origin + bucket * width, "values": {}})
            row["values"][name] = {fn: col[i] for fn, col in zip(fns, columns, strict=True)}
    return [rows[b] for b in sorted(rows)]
