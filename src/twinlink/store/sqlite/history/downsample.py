"""Downsampling for plots that keeps the peaks: min/max per bucket, and LTTB.

`minmax` splits [start, end] into points/2 equal buckets and keeps, per bucket, the smallest
and the largest sample at their own times. How depends on the size of blocks next to buckets:

- many blocks per bucket (at least `SUMMARIES_FROM`): from block summaries. SQLite finds, per
  bucket, the block with the smallest `vmin` (and the one with the largest `vmax`) among the
  blocks inside that bucket; when the extreme is the block's first or last value its time is
  t0 or t1, otherwise that one block is decoded. Blocks across bucket edges are decoded;
- blocks larger than buckets: block by block, values viewed in place and only the times at
  bucket edges and at the picks read from the blob (`BlobTimes`);
- in between: every block decoded at once (one join of the blobs).

`lttb` is Largest-Triangle-Three-Buckets (Steinarsson, 2013). Over many samples it runs on a
min/max preselection of 4 x points (MinMaxLTTB, Van Der Donckt et al., 2023): its picks stay
close to LTTB's over all samples, and its own loop runs over 4 x points samples, not the range.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.aggregate import (
    INSIDE_ONE_BUCKET,
    inside_args,
    straddling_samples,
)
from twinlink.store.sqlite.history.codec import decode_values
from twinlink.store.sqlite.history.columns import (
    EMPTY_FLOATS,
    EMPTY_TIMES,
    BlobTimes,
    Floats,
    Times,
    clip,
    numeric_block,
    numeric_column,
)
from twinlink.store.sqlite.history.queries import (
    BLOCKS_IN_RANGE,
    Series,
    blocks_by_rowid,
    count_blocks,
    holds_numbers,
)

METHODS = ("minmax", "lttb")
MINMAX_RATIO = 4
# Summaries pay off when blocks are small next to buckets; else decoding all is cheaper.
SUMMARIES_FROM = 4  # blocks per bucket

# (value, time or None when only the block's rowid is known, rowid)
_Pick = tuple[float, int | None, int]
_Arg = Callable[[Floats], Any]  # np.argmin or np.argmax


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
    width = _width(start, end, buckets)
    found = None
    if samples > budget and blocks >= enough:
        found = minmax_from_summaries(conn, s, start, end, width)
    elif samples > budget and blocks <= buckets:
        found = _minmax_by_block(conn, s, start, end, width, budget)
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
            times, values = _sample_points(times, values, start, width)
    if method == "lttb" and times.size > points:
        keep = lttb(times, values, points)
        times, values = times[keep], values[keep]
    return Downsampled(times, values, text_only=False)


def _width(start: int, end: int, buckets: int) -> int:
    return max(1, -(-(end - start + 1) // buckets))


def minmax_from_summaries(
    conn: sqlite3.Connection, s: Series, start: int, end: int, width: int
) -> tuple[Times, Floats]:
    """Min and max per bucket from the block summaries, decoding only the blocks across
    bucket edges and the blocks whose extreme lies inside them."""
    lows = _summary_picks(conn, s, start, end, width, "MIN(vmin)")
    highs = _summary_picks(conn, s, start, end, width, "MAX(vmax)")
    times, values = straddling_samples(conn, s, start, end, start, width)
    _offer_all(lows, highs, *_sample_extremes(times, values, start, width))
    _resolve_times(conn, lows, np.argmin)
    _resolve_times(conn, highs, np.argmax)
    return _points(lows, highs)


def _minmax_by_block(
    conn: sqlite3.Connection, s: Series, start: int, end: int, width: int, budget: int
) -> tuple[Times, Floats] | None:
    """Min and max per bucket from blocks larger than buckets, one block at a time: values
    are viewed in place (never joined), and of the times only those at bucket edges and at
    the picks are read. None when the range holds no more than `budget` samples."""
    rows = conn.execute(
        f"SELECT rowid, t0, t1, n, kind, vals FROM blocks WHERE {BLOCKS_IN_RANGE} "
        "ORDER BY t0, rowid",
        s.scan(start, end),
    ).fetchall()
    lows: dict[int, _Pick] = {}
    highs: dict[int, _Pick] = {}
    inside = 0
    for rowid, t0, t1, n, kind, vals in rows:
        if kind == "j":  # mixed JSON: decode it whole
            times, values = numeric_block(*blocks_by_rowid(conn, [rowid])[rowid])
            if times.size:
                times, values = clip(times, values, start, end)
            inside += times.size
            _offer_all(lows, highs, *_sample_extremes(times, values, start, width))
            continue
        with BlobTimes(conn, rowid, n, t0, t1) as stamps:
            values = decode_values(kind, vals)
            inside += _block_extremes(stamps, values, start, end, width, lows, highs)
    return None if inside <= budget else _points(lows, highs)


def _block_extremes(
    stamps: BlobTimes,
    values: npt.NDArray[Any],
    start: int,
    end: int,
    width: int,
    lows: dict[int, _Pick],
    highs: dict[int, _Pick],
) -> int:
    """Offer the min and max of each bucket's part of one block; its samples in range."""
    lo, hi = stamps.search(start), stamps.search(end + 1)
    if lo >= hi:
        return 0
    first = (stamps[lo] - start) // width
    last = (stamps[hi - 1] - start) // width
    cuts = [lo, *(stamps.search(start + k * width) for k in range(first + 1, last + 1)), hi]
    for k in range(len(cuts) - 1):
        a, b = cuts[k], cuts[k + 1]
        if a == b:
            continue
        part = values[a:b]
        i, j = a + int(part.argmin()), a + int(part.argmax())
        low, high = float(values[i]), float(values[j])
        known_low, known_high = lows.get(first + k), highs.get(first + k)
        # Only a sample that wins needs its time read.
        if known_low is None or low < known_low[0]:
            lows[first + k] = (low, stamps[i], -1)
        if known_high is None or high > known_high[0]:
            highs[first + k] = (high, stamps[j], -1)
    return hi - lo


def _offer_all(
    lows: dict[int, _Pick],
    highs: dict[int, _Pick],
    more_lows: dict[int, _Pick],
    more_highs: dict[int, _Pick],
) -> None:
    """Keep, per bucket, the smaller low and the larger high (the earlier one of equals)."""
    for b, pick in more_lows.items():
        if b not in lows or pick[0] < lows[b][0]:
            lows[b] = pick
    for b, pick in more_highs.items():
        if b not in highs or pick[0] > highs[b][0]:
            highs[b] = pick


def _points(lows: dict[int, _Pick], highs: dict[int, _Pick]) -> tuple[Times, Floats]:
    """The min and max of each bucket as samples in time order (one when they coincide)."""
    out: list[tuple[int, float]] = []
    for b in sorted(lows):
        (low_v, low_t, _), (high_v, high_t, _) = lows[b], highs[b]
        assert low_t is not None and high_t is not None
        out.extend(sorted({(low_t, low_v), (high_t, high_v)}))
    if not out:
        return EMPTY_TIMES, EMPTY_FLOATS
    t, v = zip(*out, strict=True)
    return np.asarray(t, dtype=np.int64), np.asarray(v, dtype=np.float64)


def _summary_picks(
    conn: sqlite3.Connection, s: Series, start: int, end: int, width: int, extreme: str
) -> dict[int, _Pick]:
    """Per bucket, the extreme value among the blocks inside it, and its time when the
    summary tells it (the extreme is the block's first or last value)."""
    rows = conn.execute(
        # With one min() or max() in a query, SQLite takes the other columns from that row.
        f"SELECT (t0 - ?) / ? AS b, {extreme}, t0, t1, first_v, last_v, rowid FROM blocks "
        f"WHERE {BLOCKS_IN_RANGE} AND {INSIDE_ONE_BUCKET} GROUP BY b",
        (start, width, *s.scan(start, end), *inside_args(start, end, start, width)),
    )
    picks: dict[int, _Pick] = {}
    for b, value, t0, t1, first_v, last_v, rowid in rows:
        known = t0 if value == first_v else t1 if value == last_v else None
        picks[b] = (float(value), known, rowid)
    return picks


def _extreme_indices(
    times: Times, values: Floats, origin: int, width: int
) -> tuple[list[int], list[int], list[int]]:
    """Per non-empty bucket of samples sorted by time: the bucket, and the index of its
    smallest and of its largest sample (the first of equals)."""
    first = (int(times[0]) - origin) // width
    last = (int(times[-1]) - origin) // width
    edges = origin + width * np.arange(first, last + 2, dtype=np.int64)
    bounds = np.searchsorted(times, edges, side="left")
    lo, hi = bounds[:-1], bounds[1:]
    full = hi > lo
    buckets = (np.flatnonzero(full) + first).tolist()
    spans = list(zip(lo[full].tolist(), hi[full].tolist(), strict=True))
    lows = [a + int(values[a:b].argmin()) for a, b in spans]
    highs = [a + int(values[a:b].argmax()) for a, b in spans]
    return buckets, lows, highs


def _sample_points(times: Times, values: Floats, origin: int, width: int) -> tuple[Times, Floats]:
    """The min and max of each bucket of samples sorted by time, in time order."""
    if times.size == 0:
        return times, values
    _, lows, highs = _extreme_indices(times, values, origin, width)
    low, high = np.asarray(lows), np.asarray(highs)
    picked = np.stack([np.minimum(low, high), np.maximum(low, high)], axis=1).ravel()
    picked = picked[np.r_[True, picked[1:] != picked[:-1]]]
    return times[picked], values[picked]


def _sample_extremes(
    times: Times, values: Floats, origin: int, width: int
) -> tuple[dict[int, _Pick], dict[int, _Pick]]:
    """Per bucket, the smallest and the largest of samples sorted by time, with their
    times."""
    if times.size == 0:
        return {}, {}
    buckets, lows, highs = _extreme_indices(times, values, origin, width)
    picks = []
    for index in (lows, highs):
        found = zip(buckets, values[index].tolist(), times[index].tolist(), strict=True)
        picks.append({b: (v, t, -1) for b, v, t in found})
    return picks[0], picks[1]


def _resolve_times(conn: sqlite3.Connection, picks: dict[int, _Pick], arg: _Arg) -> None:
    """Decode the blocks whose extreme is in their middle, to find its time."""
    unknown = {pick[2]: b for b, pick in picks.items() if pick[1] is None}
    if not unknown:
        return
    for rowid, (kind, tblob, vblob) in blocks_by_rowid(conn, list(unknown)).items():
        times, values = numeric_block(kind, tblob, vblob)
        i = int(arg(values))
        picks[unknown[rowid]] = (float(values[i]), int(times[i]), rowid)


def lttb(times: Times, values: Floats, points: int) -> list[int]:
    """Indices of the `points` samples Largest-Triangle-Three-Buckets keeps (the first and
    last always): per bucket, the sample making the largest triangle with the sample kept
    before it and the mean of the next bucket."""
    n = times.size
    if points >= n:
        return list(range(n))
    if points < 3:
        return [0, n - 1][:points]
    x = (times - times[0]).astype(np.float64).tolist()
    y = values.tolist()
    every = (n - 2) / (points - 2)
    picked, a = [0], 0
    for i in range(points - 2):
        lo, hi = int(i * every) + 1, int((i + 1) * every) + 1
        next_hi = min(int((i + 2) * every) + 1, n)
        cx = sum(x[hi:next_hi]) / (next_hi - hi)
        cy = sum(y[hi:next_hi]) / (next_hi - hi)
        ax, ay = x[a], y[a]
        best, best_area = lo, -1.0
        for j in range(lo, hi):
            area = abs((ax - cx) * (y[j] - ay) - (ax - x[j]) * (cy - ay))
            if area > best_area:
                best, best_area = j, area
        picked.append(best)
        a = best
    picked.append(n - 1)
    return picked
