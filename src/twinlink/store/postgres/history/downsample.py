"""Downsampling PostgreSQL history for plots, in SQL: `minmax` keeps per bucket (points / 2
equal buckets over [start, end]) the smallest and the largest sample at their own times, the
earliest of equals, as the SQLite backend does; a signal with no more than `points` samples
in the range comes back whole. `lttb` runs Largest-Triangle-Three-Buckets over a minmax
preselection of 4 x points samples (MinMaxLTTB), so its work is bounded by `points`, not by
the range. Integer signals come back exact (int64), any other numeric one as float64.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.domain.history import Downsampled
from twinlink.store.postgres.db import Connection
from twinlink.store.postgres.history.aggregate import NUMERIC
from twinlink.store.postgres.history.budget import ReadBudget
from twinlink.store.postgres.history.series import Selection

MINMAX_RATIO = 4
_RANGE = "stream_id = $1 AND series_id = ANY($2::bigint[]) AND t >= $3 AND t <= $4"
_NUMBER = "coalesce(vf, vi::float8, vb::int::float8)"
_CLASSIFY = (
    f"SELECT series_id, count(*) FILTER (WHERE {NUMERIC}), bool_and(kind = 'i') "
    f"FROM samples WHERE {_RANGE} GROUP BY series_id"
)
_ALL = f"SELECT t, vi, {_NUMBER} FROM samples WHERE {_RANGE} AND {NUMERIC} ORDER BY t, batch, pos"
# One side of each bucket: the sample with the smallest (or largest) value, earliest of
# equals; for an integer signal its int64 decides, exactly.
_SIDE = (
    "SELECT DISTINCT ON (b) (t - $3) / $5 AS b, t, vi, {number} FROM samples "
    "WHERE {range} AND {numeric} ORDER BY b, {exact} {direction}, {number} {direction}, t"
)


async def downsample(
    conn: Connection,
    found: Selection,
    start: int,
    end: int,
    points: int,
    method: str,
    budget: ReadBudget,
) -> dict[str, Downsampled]:
    kinds = {
        sid: (count, exact)
        for sid, count, exact in await conn.fetch(_CLASSIFY, found.stream_id, found.ids, start, end)
    }
    budget.values(sum(min(n, points) for n, _ in kinds.values()), "the downsample")
    per = points if method == "minmax" else points * MINMAX_RATIO
    out: dict[str, Downsampled] = {}
    for s in found.series:
        if s.id not in kinds:
            continue  # no samples in range
        count, exact = kinds[s.id]
        if count == 0:
            out[s.signal] = Downsampled(_EMPTY_T, np.empty(0, dtype=np.float64), text_only=True)
            continue
        args = (found.stream_id, [s.id], start, end)
        rows: list[Any]
        if count <= per:
            rows = await conn.fetch(_ALL, *args)
        else:
            rows = await _minmax(conn, args, per, exact)
        times = np.fromiter((r[0] for r in rows), np.int64, len(rows))
        values = _values(rows, exact)
        if method == "lttb" and times.size > points:
            keep = lttb(times, values.astype(np.float64), points)
            times, values = times[keep], values[keep]
        out[s.signal] = Downsampled(times, values, text_only=False)
    return out


_EMPTY_T: npt.NDArray[np.int64] = np.empty(0, dtype=np.int64)


async def _minmax(
    conn: Connection, args: tuple[Any, ...], per: int, exact: bool
) -> list[tuple[int, Any, float]]:
    start, end = args[2], args[3]
    buckets = max(1, per // 2)
    width = max(1, -(-(end - start + 1) // buckets))
    key = "vi" if exact else "NULL::bigint"
    sides = []
    for direction in ("ASC", "DESC"):
        sql = _SIDE.format(
            number=_NUMBER, range=_RANGE, numeric=NUMERIC, exact=key, direction=direction
        )
        sides.append({r[0]: (r[1], r[2], r[3]) for r in await conn.fetch(sql, *args, width)})
    low, high = sides
    picked: list[tuple[int, Any, float]] = []
    for b in sorted(low):
        lo, hi = low[b], high[b]
        first, second = (lo, hi) if (lo[0], 0) <= (hi[0], 1) else (hi, lo)
        picked.append(first)
        if second != first:
            picked.append(second)
    return picked


def _values(rows: list[Any], exact: bool) -> npt.NDArray[Any]:
    if exact:
        return np.fromiter((r[1] for r in rows), np.int64, len(rows))
    return np.fromiter((r[2] for r in rows), np.float64, len(rows))


def lttb(times: npt.NDArray[np.int64], values: npt.NDArray[np.float64], points: int) -> list[int]:
    """Indices of the `points` samples LTTB keeps (Steinarsson, 2013; the reference loop,
    run here over at most MINMAX_RATIO x points samples)."""
    n = times.size
    if points >= n:
        return list(range(n))
    if points < 3:
        return [0, n - 1][:points]
    x = (times - times[0]).astype(np.float64)
    y = values
    every = (n - 2) / (points - 2)
    picked, a = [0], 0
    for i in range(points - 2):
        lo, hi = int(i * every) + 1, int((i + 1) * every) + 1
        next_hi = min(int((i + 2) * every) + 1, n)
        cx, cy = x[hi:next_hi].mean(), y[hi:next_hi].mean()
        area = np.abs((x[a] - cx) * (y[lo:hi] - y[a]) - (x[a] - x[lo:hi]) * (cy - y[a]))
        a = lo + int(np.nan_to_num(area, nan=-1.0).argmax())
        picked.append(a)
    picked.append(n - 1)
    return picked
