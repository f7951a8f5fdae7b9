"""Downsampling for plots that keeps the peaks: min/max per bucket, and LTTB.

`minmax` splits [start, end] into points/2 equal buckets and keeps, per bucket, the smallest
and the largest sample at their own times (the earliest of equals). Which blocks are read
depends on the size of blocks next to buckets:

- many blocks per bucket (at least `SUMMARIES_FROM`): for the blocks inside one bucket, SQLite
  finds per bucket the one with the smallest `vmin` (and the one with the largest `vmax`),
  with its time (`tmin`, `tmax`; blocks older than those columns are decoded when the extreme
  is not their first or last value). Blocks across bucket edges go as below;
- otherwise every block by its sketch (chunked.py): the extremes of each chunk of 128
  samples, so only chunks that bucket edges cut, and that may hold an extreme, are read;
- a range of no more than `points` samples comes back whole.

`lttb` is Largest-Triangle-Three-Buckets (lttb.py). Over many samples it runs on a min/max
preselection of 4 x points (MinMaxLTTB, Van Der Donckt et al., 2023): its picks stay close to
LTTB's over all samples, and its own work is over 4 x points samples, not the range.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass

import numpy as np

from twinlink.store.sqlite.history.aggregate import INSIDE_ONE_BUCKET, inside_args
from twinlink.store.sqlite.history.chunked import minmax_of_blocks, unit_rows
from twinlink.store.sqlite.history.columns import (
    EMPTY_FLOATS,
    EMPTY_TIMES,
    Floats,
    Times,
    numeric_block,
    numeric_column,
)
from twinlink.store.sqlite.history.extremes import Candidates, Ints, bucket_points
from twinlink.store.sqlite.history.lttb import lttb
from twinlink.store.sqlite.history.queries import (
    BLOCKS_IN_RANGE,
    Series,
    blocks_by_rowid,
    count_blocks,
    holds_numbers,
)

__all__ = ["METHODS", "SUMMARIES_FROM", "Downsampled", "downsample", "lttb"]

METHODS = ("minmax", "lttb")
MINMAX_RATIO = 4
# Summaries (one SQL scan per side, no row to Python) pay off for many small blocks.
SUMMARIES_FROM = 4  # blocks per bucket


@dataclass(slots=True)
class Downsampled:
    times: Times
    values: Floats
    text_only: bool  # the signal has blocks in range, and none of them is numeric


def downsample(
    conn: sqlite3.Connection, s: Series, start: int, end: int, points: int, method: str
) -> Downsampled:
    """At most `points` samples of one signal in [start, end] (all of them when there are no
    more than that). The range must be finite (clamp it to the data first)."""
    numbers = holds_numbers(conn, s, start, end)
    if not numbers:
        return Downsampled(EMPTY_TIMES, EMPTY_FLOATS, text_only=numbers is False)
    budget = points if method == "minmax" else points * MINMAX_RATIO
    buckets = max(1, budget // 2)
    enough = SUMMARIES_FROM * buckets
    blocks, samples = count_blocks(conn, s, start, end, up_to=max(budget, enough))
    width = max(1, -(-(end - start + 1) // buckets))
    found = None
    if samples > budget and blocks >= enough:
        found = minmax_from_summaries(conn, s, start, end, width, budget)
    elif samples > budget:
        rows = unit_rows(conn, s, start, end)
        found = minmax_of_blocks(conn, rows, start, end, width, budget)
    if found is not None:
        times, values = found
    else:
        rows = conn.execute(
            f"SELECT t0, t1, kind, times, vals FROM blocks WHERE {BLOCKS_IN_RANGE} "
            "ORDER BY t0, rowid",
            s.scan(start, end),
        ).fetchall()
        times, values = numeric_column(rows, start, end)
        if times.size > budget:
            times, values = bucket_points(Candidates.of_samples(times, values, start, width))
    if method == "lttb" and times.size > points:
        keep = lttb(times, values, points)
        times, values = times[keep], values[keep]
    return Downsampled(times, values, text_only=False)


def minmax_from_summaries(
    conn: sqlite3.Connection, s: Series, start: int, end: int, width: int, budget: int
) -> tuple[Times, Floats] | None:
    """Min and max per bucket from the summaries of the blocks inside one bucket, and from
    the sketches of the blocks across bucket edges (None: see `minmax_of_blocks`)."""
    bucket, low, t_low, held = _summary_picks(conn, s, start, end, width, "MIN(vmin)", "tmin")
    _, high, t_high, _ = _summary_picks(conn, s, start, end, width, "MAX(vmax)", "tmax")
    known = Candidates(bucket, low, t_low, high, t_high)
    across = f" AND NOT ({INSIDE_ONE_BUCKET})", inside_args(start, end, start, width)
    rows = unit_rows(conn, s, start, end, *across)
    return minmax_of_blocks(conn, rows, start, end, width, budget, known, held)


def _summary_picks(
    conn: sqlite3.Connection,
    s: Series,
    start: int,
    end: int,
    width: int,
    extreme: str,
    at: str,
) -> tuple[Ints, Floats, Times, int]:
    """Per bucket, the extreme value among the blocks inside it and its time; and the
    samples of those blocks."""
    rows = conn.execute(
        # With one min() or max() in a query, SQLite takes the other columns from that row.
        f"SELECT (t0 - ?) / ? AS b, {extreme}, {at}, t0, t1, first_v, last_v, rowid, SUM(n) "
        f"FROM blocks WHERE {BLOCKS_IN_RANGE} AND {INSIDE_ONE_BUCKET} GROUP BY b ORDER BY b",
        (start, width, *s.scan(start, end), *inside_args(start, end, start, width)),
    ).fetchall()
    buckets = np.fromiter((r[0] for r in rows), np.int64, len(rows))
    values = np.fromiter((r[1] for r in rows), np.float64, len(rows))
    times = np.empty(len(rows), dtype=np.int64)
    unknown: dict[int, int] = {}  # rowid -> index (blocks written before tmin and tmax)
    for i, (_, value, at_time, t0, t1, first_v, last_v, rowid, _) in enumerate(rows):
        known = at_time if at_time is not None else _end_time(value, t0, t1, first_v, last_v)
        if known is None:
            unknown[rowid] = i
        else:
            times[i] = known
    for rowid, block in blocks_by_rowid(conn, list(unknown)).items():
        t, v = numeric_block(*block)
        i = unknown[rowid]
        times[i] = t[int(np.flatnonzero(v == values[i])[0])]
    return buckets, values, times, sum(r[8] for r in rows)


def _end_time(value: float, t0: int, t1: int, first_v: object, last_v: object) -> int | None:
    return t0 if value == first_v else t1 if value == last_v else None
