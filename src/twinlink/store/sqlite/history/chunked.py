"""Min and max per bucket from block sketches: read little more than the extremes.

Every block in range becomes units (runs of samples with known extremes): a block of
more than `sketch.CHUNK` samples gives its sketch's chunks, a smaller one its own summary
(vmin, vmax, tmin, tmax). A unit inside one bucket is a candidate as it is; the samples of
units that a bucket edge or a range end cuts are read from the blobs (only those ranges).
Blocks without a sketch (written before migration 0003) are read whole and sketched on the
way, and JSON blocks are decoded. Then numpy picks each bucket's low and high (extremes.py):
no loop per bucket.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history import sketch
from twinlink.store.sqlite.history.columns import Floats, Times, numeric_block
from twinlink.store.sqlite.history.extremes import (
    Candidates,
    Ints,
    bucket_points,
    read_ranges,
)
from twinlink.store.sqlite.history.queries import BLOCKS_IN_RANGE, Series, blocks_by_rowid


@dataclass(slots=True)
class Units:
    """Runs of samples [lo, hi) of blocks (`row` indexes the rows read), with the times of
    their first and last sample and their extremes: as columns."""

    first: Times
    last: Times
    t_low: Times
    t_high: Times
    low: Floats
    high: Floats
    row: Ints
    lo: Ints
    hi: Ints

    def take(self, which: npt.NDArray[Any]) -> Units:
        return Units(*(getattr(self, name)[which] for name in self.__slots__))

    @classmethod
    def concat(cls, parts: list[Units]) -> Units:
        names = cls.__slots__
        return cls(*(np.concatenate([getattr(p, n) for p in parts]) for n in names))


def unit_rows(
    conn: sqlite3.Connection, s: Series, start: int, end: int, where: str = "", args: Any = ()
) -> list[tuple[Any, ...]]:
    """The rows `minmax_of_blocks` takes: of the blocks touching [start, end] (and `where`)."""
    return conn.execute(
        "SELECT rowid, n, kind, t0, t1, tmin, tmax, vmin, vmax, sketch FROM blocks "
        f"WHERE {BLOCKS_IN_RANGE}{where} ORDER BY t0, rowid",
        (*s.scan(start, end), *args),
    ).fetchall()


def minmax_of_blocks(
    conn: sqlite3.Connection,
    rows: list[tuple[Any, ...]],
    start: int,
    end: int,
    width: int,
    budget: int,
    known: Candidates | None = None,
    known_held: int = 0,
) -> tuple[Times, Floats] | None:
    """The low and high sample of each bucket [start + k * width, start + (k + 1) * width)
    in [start, end], in time order, of the blocks `rows` (`unit_rows`) and the candidates
    `known` (of other blocks, holding `known_held` samples). None when all of them hold no
    more than `budget` samples in range (the caller then returns them all)."""
    units, text = _units(conn, rows)
    bucket = (units.first - start) // width
    inside = (units.first >= start) & (units.last <= end)
    inside &= bucket == (units.last - start) // width
    cut = units.take(~inside & (units.last >= start) & (units.first <= end))
    held = known_held + int(units.hi[inside].sum() - units.lo[inside].sum())
    found = Candidates(
        bucket[inside], units.low[inside], units.t_low[inside], units.high[inside],
        units.t_high[inside],
    )  # fmt: skip
    found = Candidates.concat([known, found]).reduce() if known is not None else found.reduce()
    settled = [found]
    if held > budget:  # else every sample counts: read them all
        read, extra = _settle(found, cut, start, end, width)
        cut = cut.take(read)
        settled.append(extra)
    cut = cut.take(np.lexsort((cut.lo, cut.row)))  # block by block
    picked = cut.row.tolist()
    times, values = read_ranges(
        conn,
        [rows[i][0] for i in picked],
        [rows[i][2] for i in picked],
        cut.lo.tolist(),
        cut.hi.tolist(),
    )
    times, values = _in_range(times, values, text, conn, start, end)
    if held + times.size <= budget:
        return None
    samples = Candidates.of_samples(times, values, start, width).reduce()
    return bucket_points(Candidates.concat([*settled, samples]))


def _settle(
    found: Candidates, cut: Units, start: int, end: int, width: int
) -> tuple[npt.NDArray[np.bool_], Candidates]:
    """Which units cut by bucket edges must be read, and the candidates the others give.

    A cut unit's low is the exact low of its part in the bucket holding it; its part in
    another bucket has a low no smaller, so it cannot win there when a unit inside that
    bucket is lower (likewise highs). A unit is read unless that settles both its low and
    high in each bucket it touches (two at most; three or more: always read)."""
    if found.bucket.size == 0:
        return np.ones(cut.first.size, dtype=bool), Candidates.empty()
    top = (end - start) // width
    k_low = _bucket_of(cut.t_low, start, end, width)
    k_high = _bucket_of(cut.t_high, start, end, width)
    b_first = np.clip((cut.first - start) // width, 0, top)
    b_last = np.clip((cut.last - start) // width, 0, top)
    read: npt.NDArray[np.bool_] = b_last - b_first > 1
    for b in (b_first, b_last):
        at = np.minimum(np.searchsorted(found.bucket, b), found.bucket.size - 1)
        known = found.bucket[at] == b
        read |= (b != k_low) & ~(known & (cut.low > found.low[at]))
        read |= (b != k_high) & ~(known & (cut.high < found.high[at]))
    lows, highs = ~read & (k_low >= 0), ~read & (k_high >= 0)
    n_low, n_high = int(lows.sum()), int(highs.sum())
    # A low alone comes with a high that never wins, and the other way round.
    extra = Candidates(
        bucket=np.concatenate([k_low[lows], k_high[highs]]),
        low=np.concatenate([cut.low[lows], np.full(n_high, np.inf)]),
        t_low=np.concatenate([cut.t_low[lows], np.zeros(n_high, dtype=np.int64)]),
        high=np.concatenate([np.full(n_low, -np.inf), cut.high[highs]]),
        t_high=np.concatenate([np.zeros(n_low, dtype=np.int64), cut.t_high[highs]]),
    )
    return read, extra


def _bucket_of(times: Times, start: int, end: int, width: int) -> Ints:
    """The bucket of each time, -1 when out of range."""
    inside = (times >= start) & (times <= end)
    return np.where(inside, (times - start) // width, -1)


def _units(conn: sqlite3.Connection, rows: list[tuple[Any, ...]]) -> tuple[Units, list[int]]:
    """The units of the rows, and the rowids of JSON blocks."""
    sketches: list[bytes] = []
    sketched: list[int] = []
    single: list[tuple[int, int, int, int, float, float]] = []
    singled: list[int] = []
    whole: list[int] = []
    text: list[int] = []
    for i, (rowid, n, kind, t0, t1, tmin, tmax, vmin, vmax, blob) in enumerate(rows):
        if kind == "j":
            text.append(rowid)
        elif sketch.is_sketch(blob, n):
            sketches.append(blob)
            sketched.append(i)
        elif tmin is not None and n <= sketch.CHUNK:
            single.append((t0, t1, tmin, tmax, vmin, vmax))
            singled.append(i)
        else:
            whole.append(i)
    parts = [_chunk_units(rows, sketch.columns(b"".join(sketches)), sketched)]
    if single:  # one chunk each, from the summary columns
        table = np.empty((len(single), len(sketch.FIELDS)), dtype=np.int64)
        table[:, :4] = [u[:4] for u in single]
        table.view(np.float64)[:, 4:] = [u[4:] for u in single]
        parts.append(_chunk_units(rows, (table, table.view(np.float64)), singled))
    if whole:  # written before sketches: sketch them here, a block at a time
        found = [read_ranges(conn, [rows[i][0]], [rows[i][2]], [0], [rows[i][1]]) for i in whole]
        table = np.concatenate([sketch.table(t, v) for t, v in found])
        parts.append(_chunk_units(rows, (table, table.view(np.float64)), whole))
    return Units.concat(parts), text


def _chunk_units(
    rows: list[tuple[Any, ...]], sketches: tuple[sketch.Table, Floats], which: list[int]
) -> Units:
    """The chunks of the rows `which`, from their sketches (joined)."""
    ints, floats = sketches
    # Chunk c of a block of n samples holds [c * CHUNK, min(n, (c + 1) * CHUNK)).
    n = np.asarray([rows[i][1] for i in which], dtype=np.int64)
    k = -(-n // sketch.CHUNK)
    c = np.arange(ints.shape[0], dtype=np.int64) - np.repeat(np.cumsum(k) - k, k)
    lo = c * sketch.CHUNK
    return Units(
        first=ints[:, 0],
        last=ints[:, 1],
        t_low=ints[:, 2],
        t_high=ints[:, 3],
        low=floats[:, 4],
        high=floats[:, 5],
        row=np.repeat(np.asarray(which, dtype=np.int64), k),
        lo=lo,
        hi=np.minimum(lo + sketch.CHUNK, np.repeat(n, k)),
    )


def _in_range(
    times: Times, values: Floats, text: list[int], conn: sqlite3.Connection, start: int, end: int
) -> tuple[Times, Floats]:
    """The samples in [start, end], with the numbers of the JSON blocks `text` added."""
    if text:
        parts = [numeric_block(*b) for b in blocks_by_rowid(conn, text).values()]
        times = np.concatenate([times, *(t for t, _ in parts)])
        values = np.concatenate([values, *(v for _, v in parts)])
    keep = (times >= start) & (times <= end)
    if not keep.all():
        times, values = times[keep], values[keep]
    return times, values
