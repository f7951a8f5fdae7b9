"""The smallest and the largest sample per bucket, from candidates, with numpy only.

A candidate is (bucket, value, time): a sample, or the extreme of a chunk or block that lies
inside one bucket (floats, or int64 where integers must stay exact). Per bucket the smallest
(largest) value wins, and of equal values the earliest; a bucket's low and high come out as
one or two samples in time order.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import cast

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.codec import TIME_DTYPE, VALUE_DTYPES
from twinlink.store.sqlite.history.columns import EMPTY_FLOATS, EMPTY_TIMES, Floats, Times, Values

Ints = npt.NDArray[np.int64]


@dataclass(slots=True)
class Candidates:
    bucket: Ints
    low: Values  # float64, or int64 for exact integers
    t_low: Times
    high: Values
    t_high: Times

    @classmethod
    def empty(cls) -> Candidates:
        ints, floats = np.empty(0, dtype=np.int64), np.empty(0, dtype=np.float64)
        return cls(ints, floats, ints, floats, ints)

    @classmethod
    def concat(cls, parts: list[Candidates]) -> Candidates:
        names = cls.__slots__
        return cls(*(np.concatenate([getattr(p, n) for p in parts]) for n in names))

    def reduce(self) -> Candidates:
        """One candidate per bucket (its low and its high), by bucket."""
        if self.bucket.size == 0:
            return self
        b, low, t_low = best_per_bucket(self.bucket, self.low, self.t_low, smallest=True)
        _, high, t_high = best_per_bucket(self.bucket, self.high, self.t_high, smallest=False)
        return Candidates(b, low, t_low, high, t_high)

    @classmethod
    def of_samples(cls, times: Times, values: Values, origin: int, width: int) -> Candidates:
        return cls((times - origin) // width, values, times, values, times)


def best_per_bucket(
    bucket: Ints, value: Values, time: Times, smallest: bool
) -> tuple[Ints, Values, Times]:
    """(buckets, values, times): per bucket the smallest (or largest) value, the earliest of
    equals. Values must not be NaN."""
    if bucket.size > 1 and bool(np.any(bucket[1:] < bucket[:-1])):
        order = np.argsort(bucket, kind="stable")
        bucket, value, time = bucket[order], value[order], time[order]
    starts = _run_starts(bucket)
    best = (np.minimum if smallest else np.maximum).reduceat(value, starts)
    hit = value == np.repeat(best, np.diff(np.append(starts, bucket.size)))
    hit_bucket, hit_time = bucket[hit], time[hit]
    earliest = np.minimum.reduceat(hit_time, _run_starts(hit_bucket))
    return bucket[starts], best, earliest


def _run_starts(sorted_keys: Ints) -> npt.NDArray[np.intp]:
    new = np.empty(sorted_keys.size, dtype=bool)
    new[:1] = True
    np.not_equal(sorted_keys[1:], sorted_keys[:-1], out=new[1:])
    return np.flatnonzero(new)


def bucket_points(c: Candidates) -> tuple[Times, Values]:
    """The low and the high sample of each bucket in time order (one when they are the
    same sample)."""
    _, times, values = keyed_points(c)
    return times, values


def keyed_points(c: Candidates) -> tuple[Ints, Times, Values]:
    """`bucket_points`, with the bucket of each point."""
    if c.bucket.size == 0:
        return np.empty(0, dtype=np.int64), EMPTY_TIMES, EMPTY_FLOATS
    one = c.reduce()
    lv, lt, hv, ht = one.low, one.t_low, one.high, one.t_high
    low_first = (lt < ht) | ((lt == ht) & (lv <= hv))
    times = np.stack([np.where(low_first, lt, ht), np.where(low_first, ht, lt)], axis=1)
    values = np.stack([np.where(low_first, lv, hv), np.where(low_first, hv, lv)], axis=1)
    keep = np.ones(times.shape, dtype=bool)
    keep[:, 1] = (lt != ht) | (lv != hv)
    buckets = np.stack([one.bucket, one.bucket], axis=1)
    return buckets[keep], times[keep], values[keep]


def read_ranges(
    conn: sqlite3.Connection, rowid: list[int], kind: list[str], lo: list[int], hi: list[int]
) -> tuple[Times, Floats]:
    """The samples [lo, hi) of numeric blocks (by rowid), read straight from their blobs,
    concatenated in the order given (ranges of one block next to each other)."""
    time_parts: list[bytes] = []
    value_parts: list[bytes] = []
    kinds: list[str] = []
    i, count = 0, len(rowid)
    while i < count:
        size = VALUE_DTYPES[kind[i]].itemsize
        with (
            conn.blobopen("blocks", "times", rowid[i], readonly=True) as times,
            conn.blobopen("blocks", "vals", rowid[i], readonly=True) as vals,
        ):
            j = i
            while j < count and rowid[j] == rowid[i]:
                a, b = lo[j], hi[j]
                while j + 1 < count and rowid[j + 1] == rowid[i] and lo[j + 1] == b:
                    j += 1  # one read for neighbouring ranges
                    b = hi[j]
                # (typeshed has Blob slices as int; they are bytes)
                time_parts.append(cast(bytes, times[8 * a : 8 * b]))
                value_parts.append(cast(bytes, vals[size * a : size * b]))
                kinds.append(kind[i])
                j += 1
        i = j
    return _join(time_parts, value_parts, kinds)


def _join(
    time_parts: list[bytes], value_parts: list[bytes], kinds: list[str]
) -> tuple[Times, Floats]:
    times = np.frombuffer(b"".join(time_parts), dtype=TIME_DTYPE)
    if len(set(kinds)) <= 1:
        dtype = VALUE_DTYPES[kinds[0]] if kinds else np.dtype("<f8")
        raw = np.frombuffer(b"".join(value_parts), dtype=dtype)
        return times, raw.astype(np.float64, copy=False)
    parts = [
        np.frombuffer(p, dtype=VALUE_DTYPES[k]) for p, k in zip(value_parts, kinds, strict=True)
    ]
    return times, np.concatenate(parts).astype(np.float64)
