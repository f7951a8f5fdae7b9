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

The signals with few samples (no more than they may return) are read together, a page at a
time, in one statement for all of them; which signal holds what comes from one statement too
(scan.classify). Only a signal with more samples takes statements of its own, paid for by
those samples. Integer signals come back exact: their sketches and summaries are floats, so
a signal with values of 2^53 or more is read from its int64 blobs instead.

`lttb` is Largest-Triangle-Three-Buckets (lttb.py). Over many samples it runs on a min/max
preselection of 4 x points (MinMaxLTTB, Van Der Donckt et al., 2023): its picks stay close to
LTTB's over all samples, and its own work is over 4 x points samples, not the range.
"""

from __future__ import annotations

import itertools
import sqlite3
from collections.abc import Iterator
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.domain.history import Downsampled
from twinlink.store.sqlite.history.aggregate import INSIDE_ONE_BUCKET, inside_args
from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.chunked import minmax_of_blocks, unit_rows
from twinlink.store.sqlite.history.columns import (
    EMPTY_FLOATS,
    EMPTY_TIMES,
    Floats,
    Times,
    Values,
    numeric_block,
    numeric_blocks,
    numeric_column,
)
from twinlink.store.sqlite.history.extremes import Candidates, Ints, bucket_points, keyed_points
from twinlink.store.sqlite.history.lttb import lttb
from twinlink.store.sqlite.history.queries import BLOCKS_IN_RANGE, Series, blocks_by_rowid
from twinlink.store.sqlite.history.scan import (
    PAGE_SAMPLES,
    WHERE,
    Kinds,
    SeriesSet,
    classify,
)

__all__ = ["SUMMARIES_FROM", "downsample", "lttb"]

MINMAX_RATIO = 4
# Summaries (one SQL scan per side, no row to Python) pay off for many small blocks.
SUMMARIES_FROM = 4  # blocks per bucket
# Signals of up to this many times `points` samples (at least TOGETHER_FROM, at most a few
# pages) are read together, from their samples; those with more take statements of their
# own, whose summaries and sketches spare reading most of their samples.
TOGETHER_FACTOR = 16
TOGETHER_FROM = 8_192
TOGETHER_UP_TO = 4 * PAGE_SAMPLES


def downsample(
    conn: sqlite3.Connection,
    series: list[Series],
    start: int,
    end: int,
    points: int,
    method: str,
    budget: ReadBudget,
) -> dict[str, Downsampled]:
    """Per signal, at most `points` samples in [start, end] (all of them when there are no
    more than that). The range must be finite (clamp it to the data first).

    Which signals hold what comes from one statement for all of them. Signals of few samples
    (TOGETHER_FACTOR) are read together, a page at a time, in one statement for all; only a
    signal with more takes statements of its own, paid for by its samples."""
    sset = SeriesSet.of(series)
    kinds = classify(conn, sset, start, end)
    held = np.minimum(kinds.samples[kinds.numeric], points)
    budget.values(int(held.sum()), "the downsample")
    per = points if method == "minmax" else points * MINMAX_RATIO
    found: dict[int, Downsampled] = {
        int(i): Downsampled(EMPTY_TIMES, EMPTY_FLOATS, text_only=True)
        for i in np.flatnonzero(kinds.text_only)
    }
    few = min(max(TOGETHER_FACTOR * per, TOGETHER_FROM), TOGETHER_UP_TO)
    together = kinds.numeric & (kinds.samples <= few)
    for i, times, values in _together(conn, sset, together, kinds.integer, start, end, per, budget):
        found[i] = Downsampled(times, values, text_only=False)
    for i in np.flatnonzero(kinds.numeric & ~together).tolist():
        budget.check()
        times, values = _many(conn, series[i], kinds, i, start, end, per, budget)
        found[i] = Downsampled(times, values, text_only=False)
    if method == "lttb":
        for d in found.values():
            if d.times.size > points:
                keep = lttb(d.times, d.values, points)
                d.times, d.values = d.times[keep], d.values[keep]
    return {series[i].signal: found[i] for i in sorted(found)}


def _together(
    conn: sqlite3.Connection,
    sset: SeriesSet,
    which: npt.NDArray[np.bool_],
    integer: npt.NDArray[np.bool_],
    start: int,
    end: int,
    per: int,
    budget: ReadBudget,
) -> Iterator[tuple[int, Times, Values]]:
    """(position, times, values) of the series `which`: every sample in [start, end], or
    each bucket's min and max when a series has more than `per`. Read together a page at a
    time (a series is never split between pages), from the samples themselves."""
    part = sset.subset(which.tolist())
    if not len(part):
        return
    at = np.flatnonzero(which)  # position in `sset` of each position in `part`
    exact = integer[which]
    cursor = conn.execute(
        f"SELECT series_id, n, kind, times, vals FROM blocks WHERE {WHERE} "
        "ORDER BY series_id, t0, rowid",
        part.scan(start, end),
    )
    page: list[Any] = []
    while rows := cursor.fetchmany(256):
        page.extend(rows)
        if sum(r[1] for r in page) >= PAGE_SAMPLES:
            last = page[-1][0]  # a series whose blocks may go on in the next rows waits
            ready = [r for r in page if r[0] != last]
            page = [r for r in page if r[0] == last]
            for want in (True, False):
                yield from _page(ready, part, at, exact, want, start, end, per)
            budget.check()
    for want in (True, False):
        yield from _page(page, part, at, exact, want, start, end, per)


def _page(
    rows: list[Any],
    part: SeriesSet,
    at: npt.NDArray[np.intp],
    exact: npt.NDArray[np.bool_],
    ints: bool,
    start: int,
    end: int,
    per: int,
) -> Iterator[tuple[int, Times, Values]]:
    """The series of `rows` of one kind (integers, or floats), all of them in numpy steps."""
    series = part.position(np.asarray([r[0] for r in rows], dtype=np.int64))
    pick = np.flatnonzero(exact[series] == ints).tolist()
    if not pick:
        return
    times, values, sizes = numeric_blocks([rows[i][2:] for i in pick], exact=ints)
    owner = np.repeat(series[pick], sizes)
    keep = (times >= start) & (times <= end)
    times, values, owner = times[keep], values[keep], owner[keep]
    order = np.lexsort((times, owner))  # stable: equal times keep block order
    times, values, owner = times[order], values[order], owner[order]
    many = np.zeros(len(part), dtype=bool)
    many[owner] = np.bincount(owner, minlength=len(part))[owner] > per
    whole = ~many[owner]
    yield from _by_owner(at, owner[whole], times[whole], values[whole])
    if not whole.all():  # min and max per (series, bucket), as one set of buckets
        buckets = max(1, per // 2)
        width = max(1, -(-(end - start + 1) // buckets))
        t, v, o = times[~whole], values[~whole], owner[~whole]
        key = o.astype(np.int64) * buckets + (t - start) // width
        keys, t, v = keyed_points(Candidates(key, v, t, v, t))
        yield from _by_owner(at, (keys // buckets).astype(np.intp), t, v)


def _by_owner(
    at: npt.NDArray[np.intp], owner: npt.NDArray[np.intp], times: Times, values: Values
) -> Iterator[tuple[int, Times, Values]]:
    if owner.size == 0:
        return
    bounds = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1], True]).tolist()
    for a, b in itertools.pairwise(bounds):
        yield int(at[owner[a]]), times[a:b], values[a:b]


def _many(
    conn: sqlite3.Connection,
    s: Series,
    kinds: Kinds,
    i: int,
    start: int,
    end: int,
    per: int,
    budget: ReadBudget,
) -> tuple[Times, Values]:
    """Min and max per bucket of one signal with more than `per` samples in its blocks."""
    buckets = max(1, per // 2)
    width = max(1, -(-(end - start + 1) // buckets))
    if kinds.integer[i] and kinds.big[i]:  # floats would round its values: read them exact
        return _exact_minmax(conn, s, start, end, per, width, budget)
    found = None
    if kinds.blocks[i] >= SUMMARIES_FROM * buckets:
        found = minmax_from_summaries(conn, s, start, end, width, per)
    else:
        found = minmax_of_blocks(conn, unit_rows(conn, s, start, end), start, end, width, per)
    if found is not None:
        times, values = found
    else:  # blocks stick out of the range: it holds no more than `per` samples
        rows = conn.execute(
            f"SELECT t0, t1, kind, times, vals FROM blocks WHERE {BLOCKS_IN_RANGE} "
            "ORDER BY t0, rowid",
            s.scan(start, end),
        ).fetchall()
        times, values = numeric_column(rows, start, end)
        if times.size > per:
            times, values = bucket_points(Candidates.of_samples(times, values, start, width))
    if kinds.integer[i]:  # every value is below 2^53: its float is the exact integer
        return times, values.astype(np.int64)
    return times, values


def _exact_minmax(
    conn: sqlite3.Connection,
    s: Series,
    start: int,
    end: int,
    per: int,
    width: int,
    budget: ReadBudget,
) -> tuple[Times, Values]:
    """Min and max per bucket of an integer signal, from its int64 blobs, a page of blocks
    at a time: exact where float64 would round (values of 2^53 and more)."""
    cursor = conn.execute(
        f"SELECT kind, times, vals FROM blocks WHERE {BLOCKS_IN_RANGE} ORDER BY t0, rowid",
        s.scan(start, end),
    )
    kept: list[tuple[Times, Values]] = []  # every sample while they are no more than `per`
    held = 0
    picked: list[Candidates] = []
    while rows := cursor.fetchmany(64):
        times, values, _ = numeric_blocks(rows, exact=True)
        keep = (times >= start) & (times <= end)
        kept.append((times[keep], values[keep]))
        held += int(keep.sum())
        if held > per:
            picked.extend(Candidates.of_samples(t, v, start, width).reduce() for t, v in kept)
            kept = []
            if len(picked) > 64:
                picked = [Candidates.concat(picked).reduce()]
        budget.check()
    if picked:
        return bucket_points(Candidates.concat(picked))
    times = np.concatenate([EMPTY_TIMES, *(t for t, _ in kept)])
    values = np.concatenate([np.empty(0, dtype=np.int64), *(v for _, v in kept)])
    order = np.argsort(times, kind="stable")
    return times[order], values[order]


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
