"""Aggregation over fixed time buckets, for all the signals of a query at once, from block
summaries where it can.

A block that lies inside [start, end] and inside one bucket adds its stored summary (count,
sum, min, max, first, last) to that bucket; SQLite groups those summaries itself, per signal
and bucket, in three statements for every signal of the query. The other blocks (across a
bucket edge or a range end, JSON blocks, and integer blocks whose REAL summary is not exact)
are read in one statement, in pages, and decoded with numpy for all signals together.

Integer signals stay exact (partials.py): a summary is used for them only when its REAL
columns hold the exact integers (every |value| times the block's count below 2^53); other
blocks are read from their int64 blobs.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from typing import Any

import numpy as np

from twinlink.domain.history import Aggregated
from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.columns import numeric_blocks
from twinlink.store.sqlite.history.partials import Partials, sample_partials
from twinlink.store.sqlite.history.queries import Series
from twinlink.store.sqlite.history.scan import PAGE_SAMPLES, WHERE, SeriesSet, classify

# A block wholly inside [start, end] and inside one bucket: bucket(t) = (t - origin) / width.
INSIDE_ONE_BUCKET = "kind != 'j' AND t0 >= ? AND t1 <= ? AND (t0 - ?) / ? = (t1 - ?) / ?"
# A block whose REAL vmin, vmax and vsum are its exact values (integer blocks: every partial
# sum below 2^53 in magnitude).
EXACT_SUMMARY = "(kind <> 'i' OR n * MAX(ABS(vmin), ABS(vmax)) < 9007199254740992.0)"
_SUMMARY = f"{WHERE} AND {INSIDE_ONE_BUCKET} AND {EXACT_SUMMARY}"
_SPLIT = 26  # integer vsum (< 2^53) summed in SQL as high and low parts, which cannot overflow


def inside_args(start: int, end: int, origin: int, width: int) -> tuple[int, ...]:
    return (start, end, origin, width, origin, width)


def aggregate(
    conn: sqlite3.Connection,
    series: list[Series],
    start: int,
    end: int,
    width: int,
    fns: list[str],
    budget: ReadBudget,
    origin: int = 0,
) -> Aggregated:
    """Rows {time: bucket start, values: {signal: {fn: value}}} over buckets
    [origin + k * width, origin + (k + 1) * width) in [start, end]; empty buckets left out."""
    sset = SeriesSet.of(series)
    kinds = classify(conn, sset, start, end)
    text = [s.signal for s, t in zip(series, kinds.text_only.tolist(), strict=True) if t]
    numbers = sset.subset(kinds.numeric.tolist())
    if not len(numbers):
        return Aggregated([], text)
    buckets = (end - origin) // width - (start - origin) // width + 1
    held = np.minimum(kinds.samples[kinds.numeric], buckets)
    budget.values(int(held.sum()) * len(fns), "the aggregate")
    exact = kinds.integer[kinds.numeric]  # by position in `numbers`
    tables = _summaries(conn, numbers, exact, start, end, width, origin)
    for part in _straddling(conn, numbers, exact, start, end, width, origin, budget):
        tables.append(part)
        budget.check()
    ints = Partials.concat([Partials.empty(True), *(t for t in tables if t.exact)])
    floats = Partials.concat([Partials.empty(False), *(t for t in tables if not t.exact)])
    names = [s.signal for s in numbers.series]
    tables = [ints.reduce(), floats.reduce()]
    return Aggregated(aggregate_rows(names, tables, fns, width, origin), text)


def _summaries(
    conn: sqlite3.Connection,
    sset: SeriesSet,
    exact: np.ndarray[Any, np.dtype[np.bool_]],
    start: int,
    end: int,
    width: int,
    origin: int,
) -> list[Partials]:
    """Partials from the summaries of the blocks inside one bucket: an integer and a float
    table."""
    args = (origin, width, *sset.scan(start, end), *inside_args(start, end, origin, width))
    sums = conn.execute(
        f"SELECT series_id, (t0 - ?) / ? AS b, SUM(n), SUM(vsum), MIN(vmin), MAX(vmax), "
        f"SUM(CASE WHEN kind = 'i' THEN CAST(vsum AS INTEGER) >> {_SPLIT} END), "
        f"SUM(CASE WHEN kind = 'i' THEN CAST(vsum AS INTEGER) & {(1 << _SPLIT) - 1} END) "
        f"FROM blocks WHERE {_SUMMARY} GROUP BY series_id, b ORDER BY series_id, b",
        args,
    ).fetchall()
    if not sums:
        return []
    # With one min() or max() in a query, SQLite takes the other columns from that row.
    firsts = conn.execute(
        f"SELECT (t0 - ?) / ? AS b, MIN(t0), first_v FROM blocks WHERE {_SUMMARY} "
        "GROUP BY series_id, b ORDER BY series_id, b",
        args,
    ).fetchall()
    lasts = conn.execute(
        f"SELECT (t0 - ?) / ? AS b, MAX(t1), last_v FROM blocks WHERE {_SUMMARY} "
        "GROUP BY series_id, b ORDER BY series_id, b",
        args,
    ).fetchall()
    series = sset.position(np.asarray([r[0] for r in sums], dtype=np.int64))
    is_int = exact[series]
    tables = []
    for want in (True, False):
        pick = np.flatnonzero(is_int == want).tolist()
        if pick:
            tables.append(_summary_table(sums, firsts, lasts, series, pick, want))
    return tables


def _summary_table(
    sums: list[Any], firsts: list[Any], lasts: list[Any], series: Any, pick: list[int], ints: bool
) -> Partials:
    rows = [sums[i] for i in pick]
    value = np.int64 if ints else np.float64
    if ints:
        total = np.empty(len(rows), dtype=object)
        total[:] = [(r[6] << _SPLIT) + r[7] for r in rows]
    else:
        total = np.asarray([r[3] for r in rows], dtype=np.float64)
    return Partials(
        series=series[pick],
        bucket=np.asarray([r[1] for r in rows], dtype=np.int64),
        count=np.asarray([r[2] for r in rows], dtype=np.int64),
        total=total,
        low=np.asarray([r[4] for r in rows]).astype(value),
        high=np.asarray([r[5] for r in rows]).astype(value),
        first_t=np.asarray([firsts[i][1] for i in pick], dtype=np.int64),
        first_v=np.asarray([firsts[i][2] for i in pick]).astype(value),
        last_t=np.asarray([lasts[i][1] for i in pick], dtype=np.int64),
        last_v=np.asarray([lasts[i][2] for i in pick]).astype(value),
    )


def _straddling(
    conn: sqlite3.Connection,
    sset: SeriesSet,
    exact: np.ndarray[Any, np.dtype[np.bool_]],
    start: int,
    end: int,
    width: int,
    origin: int,
    budget: ReadBudget,
) -> Iterator[Partials]:
    """Partials of the samples in [start, end] of the blocks not summarised, a page of
    about PAGE_SAMPLES samples at a time (all signals together)."""
    cursor = conn.execute(
        f"SELECT series_id, n, kind, times, vals FROM blocks WHERE {WHERE} "
        f"AND NOT ({INSIDE_ONE_BUCKET} AND {EXACT_SUMMARY}) ORDER BY series_id, t0, rowid",
        (*sset.scan(start, end), *inside_args(start, end, origin, width)),
    )
    page: list[Any] = []
    held = 0
    while rows := cursor.fetchmany(256):
        page.extend(rows)
        held += sum(r[1] for r in rows)
        if held >= PAGE_SAMPLES:
            yield from _page_partials(page, sset, exact, start, end, width, origin)
            page, held = [], 0
            budget.check()
    if page:
        yield from _page_partials(page, sset, exact, start, end, width, origin)


def _page_partials(
    rows: list[Any],
    sset: SeriesSet,
    exact: np.ndarray[Any, np.dtype[np.bool_]],
    start: int,
    end: int,
    width: int,
    origin: int,
) -> Iterator[Partials]:
    at = sset.position(np.asarray([r[0] for r in rows], dtype=np.int64))
    is_int = exact[at]
    for want in (True, False):
        pick = np.flatnonzero(is_int == want).tolist()
        if not pick:
            continue
        times, values, sizes = numeric_blocks([rows[i][2:] for i in pick], exact=want)
        series = np.repeat(at[pick], sizes)
        keep = (times >= start) & (times <= end)
        times, values, series = times[keep], values[keep], series[keep]
        order = np.lexsort((times, series))  # stable: equal times keep block order
        yield sample_partials(times[order], values[order], series[order], origin, width)


def aggregate_rows(
    names: list[str], tables: list[Partials], fns: list[str], width: int, origin: int = 0
) -> list[dict[str, Any]]:
    """Rows joined on the bucket start: {time, values: {signal: {fn: value}}}, signals in
    the order of `names`."""
    entries: list[tuple[int, int, dict[str, Any]]] = []
    for p in tables:
        columns = [p.values(fn) for fn in fns]
        for i, (bucket, series) in enumerate(
            zip(p.bucket.tolist(), p.series.tolist(), strict=True)
        ):
            entries.append(
                (bucket, series, {fn: col[i] for fn, col in zip(fns, columns, strict=True)})
            )
    entries.sort(key=lambda e: (e[0], e[1]))
    rows: list[dict[str, Any]] = []
    for bucket, series, value in entries:
        if not rows or rows[-1]["bucket"] != bucket:
            rows.append({"bucket": bucket, "time": origin + bucket * width, "values": {}})
        rows[-1]["values"][names[series]] = value
    for row in rows:
        del row["bucket"]
    return rows
