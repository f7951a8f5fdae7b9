"""Largest-Triangle-Three-Buckets (Steinarsson, 2013), exact and mostly in numpy.

LTTB keeps the first and last sample and, per bucket, the sample making the largest triangle
with the sample kept before it and the mean of the next bucket. Only "the sample kept before"
chains the buckets, and it is one of the previous bucket's few samples: so the areas of every
(previous pick, candidate) pair are computed at once, and the chain is then followed through
a small table. With large buckets (over `_TABLE_CELLS` pairs in all) each bucket is one numpy
step instead. Either way the picks are those of the reference loop, float for float.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.columns import Floats, Times

_TABLE_CELLS = 1 << 20
_SUM_STEPS = 64
Index = npt.NDArray[np.intp]


def lttb(times: Times, values: Floats, points: int) -> list[int]:
    """Indices of the `points` samples LTTB keeps (all of them when there are no more)."""
    n = times.size
    if points >= n:
        return list(range(n))
    if points < 3:
        return [0, n - 1][:points]
    x = (times - times[0]).astype(np.float64)
    y = np.asarray(values, dtype=np.float64)
    every = (n - 2) / (points - 2)
    steps = np.arange(points - 2, dtype=np.float64)
    lo = (steps * every).astype(np.intp) + 1
    hi = ((steps + 1) * every).astype(np.intp) + 1
    next_hi = np.minimum(((steps + 2) * every).astype(np.intp) + 1, n)
    cx, cy = _means(x, hi, next_hi), _means(y, hi, next_hi)
    widest = int((hi - lo).max())
    if (points - 2) * widest * widest <= _TABLE_CELLS:
        picked = _by_table(x, y, lo, hi, cx, cy, widest)
    else:
        picked = _by_bucket(x, y, lo, hi, cx, cy)
    return [0, *picked, n - 1]


def _means(v: Floats, lo: Index, hi: Index) -> Floats:
    """The mean of each v[lo:hi], summed left to right as Python's sum() does (so the picks
    match the reference loop): one numpy step per position in the longest slice."""
    count = hi - lo
    longest = int(count.max())
    if longest > _SUM_STEPS:
        vs = v.tolist()
        pairs = zip(lo.tolist(), hi.tolist(), strict=True)
        sums: Floats = np.asarray([sum(vs[a:b]) for a, b in pairs])
        return sums / count
    total = np.zeros(lo.size, dtype=np.float64)
    for k in range(longest):
        # Past its end a slice adds 0.0, which changes no sum.
        total += np.where(k < count, v[np.minimum(lo + k, v.size - 1)], 0.0)
    return total / count


def _area(ax: Floats, ay: Floats, cx: Floats, cy: Floats, jx: Floats, jy: Floats) -> Floats:
    """Twice the triangle (a, j, c), as the reference computes it; NaN counts as -1."""
    area = np.abs((ax - cx) * (jy - ay) - (ax - jx) * (cy - ay))
    return np.where(np.isnan(area), -1.0, area)


def _by_table(
    x: Floats, y: Floats, lo: Index, hi: Index, cx: Floats, cy: Floats, widest: int
) -> list[int]:
    k = np.arange(widest)
    cand = lo[:, None] + k  # bucket i's candidates j (padded)
    valid = k < (hi - lo)[:, None]
    cand = np.minimum(cand, x.size - 1)
    # The previous pick a of bucket i is one of bucket i - 1's candidates (of the first: 0).
    prev = np.vstack([np.zeros((1, widest), dtype=cand.dtype), cand[:-1]])
    ax, ay = x[prev][:, :, None], y[prev][:, :, None]
    jx, jy = x[cand][:, None, :], y[cand][:, None, :]
    area = _area(ax, ay, cx[:, None, None], cy[:, None, None], jx, jy)
    area = np.where(valid[:, None, :], area, -np.inf)
    # best[i * widest + previous candidate] -> candidate: one flat list, no list per bucket
    best = area.argmax(axis=2).ravel().tolist()
    picked, choice = [], 0
    for row, first in enumerate(lo.tolist()):
        choice = best[row * widest + choice]
        picked.append(first + choice)
    return picked


def _by_bucket(x: Floats, y: Floats, lo: Index, hi: Index, cx: Floats, cy: Floats) -> list[int]:
    picked, a = [], 0
    for i, (first, stop) in enumerate(zip(lo.tolist(), hi.tolist(), strict=True)):
        area = _area(x[a], y[a], cx[i], cy[i], x[first:stop], y[first:stop])
        a = first + int(area.argmax())
        picked.append(a)
    return picked
