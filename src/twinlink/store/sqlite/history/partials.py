"""Partial aggregates per (signal, bucket), reduced with numpy: no loop per bucket or signal.

Two kinds of tables: floats (numbers, bools as 0 and 1), and exact integers for signals that
hold only int64 values. Integers stay integers: min, max, first and last are int64, and sums
are Python ints (a sum of int64 values may not fit in 64 bits), added up in two halves of
32 bits so numpy never overflows.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.columns import Times, Values

Ints = npt.NDArray[np.int64]
Index = npt.NDArray[np.intp]


@dataclass(slots=True)
class Partials:
    """Partial aggregates, one per (series, bucket, source); `reduce` makes them one per
    (series, bucket). `total` holds Python ints in an integer table, floats otherwise."""

    series: Index
    bucket: Ints
    count: Ints
    total: Values
    low: Values
    high: Values
    first_t: Times
    first_v: Values
    last_t: Times
    last_v: Values

    def __len__(self) -> int:
        return int(self.bucket.size)

    @classmethod
    def empty(cls, exact: bool) -> Partials:
        ints = np.empty(0, dtype=np.int64)
        values = np.empty(0, dtype=np.int64 if exact else np.float64)
        total = np.empty(0, dtype=object if exact else np.float64)
        index = np.empty(0, dtype=np.intp)
        return cls(index, ints, ints, total, values, values, ints, values, ints, values)

    @property
    def exact(self) -> bool:
        return bool(self.total.dtype == object)

    @classmethod
    def concat(cls, parts: list[Partials]) -> Partials:
        names = cls.__slots__
        return cls(*(np.concatenate([getattr(p, n) for p in parts]) for n in names))

    def reduce(self) -> Partials:
        if len(self) == 0:
            return self
        order = np.lexsort((self.first_t, self.bucket, self.series))  # stable
        s, b = self.series[order], self.bucket[order]
        new = np.empty(b.size, dtype=bool)
        new[0] = True
        new[1:] = (b[1:] != b[:-1]) | (s[1:] != s[:-1])
        starts = np.flatnonzero(new)
        by_last = np.lexsort((self.last_t, self.bucket, self.series))
        ends = np.r_[starts[1:], b.size] - 1
        return Partials(
            series=s[starts],
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
        """One function's column as Python values. In an integer table `avg` is a float and
        `sum` a Python int, exact however large."""
        if fn == "avg":
            if self.exact:
                return [
                    t / c for t, c in zip(self.total.tolist(), self.count.tolist(), strict=True)
                ]
            return (self.total / np.maximum(self.count, 1)).tolist()  # type: ignore[no-any-return]
        column = {
            "min": self.low,
            "max": self.high,
            "count": self.count,
            "first": self.first_v,
            "last": self.last_v,
            "sum": self.total,
        }[fn]
        return column.tolist()  # type: ignore[no-any-return]


def exact_sums(values: Ints, starts: Index) -> Values:
    """Sums of the runs of int64 values beginning at `starts`, as Python ints: the high and
    the low 32 bits are summed apart, which cannot overflow for runs under 2^31 values."""
    high = np.add.reduceat(values >> 32, starts)
    low = np.add.reduceat(values & 0xFFFFFFFF, starts)
    return high.astype(object) * (1 << 32) + low.astype(object)  # type: ignore[no-any-return]


def sample_partials(
    times: Times, values: Values, series: Index, origin: int, width: int
) -> Partials:
    """Per (series, bucket) partials of samples sorted by series, then time (each bucket of
    a series is one contiguous run). int64 values give an integer table."""
    exact = values.dtype == np.int64
    if times.size == 0:
        return Partials.empty(exact)
    b = (times - origin) // width
    new = np.empty(b.size, dtype=bool)
    new[0] = True
    new[1:] = (b[1:] != b[:-1]) | (series[1:] != series[:-1])
    starts = np.flatnonzero(new)
    ends = np.r_[starts[1:], b.size] - 1
    return Partials(
        series=series[starts],
        bucket=b[starts],
        count=np.diff(np.r_[starts, b.size]).astype(np.int64),
        total=exact_sums(values, starts) if exact else np.add.reduceat(values, starts),
        low=np.minimum.reduceat(values, starts),
        high=np.maximum.reduceat(values, starts),
        first_t=times[starts],
        first_v=values[starts],
        last_t=times[ends],
        last_v=values[ends],
    )
