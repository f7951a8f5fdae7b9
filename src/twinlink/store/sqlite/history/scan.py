"""Reading the blocks of many series at once: one SQL statement for all the signals of a
query, never one per signal.

The series of a query go to SQLite as one JSON array (`series_id IN (SELECT value FROM
json_each(?))`), which it walks with `blocks_by_series_time` like a single series; so a stream
of 20 000 signals costs statements in proportion to its pages of data, not to its signals.
`time_pages` gives the blocks of all the series in time order, in pages of bounded size: the
merge into rows (merge.py) and the export read them so, in constant memory.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import orjson

from twinlink.domain.history import MIN_TIME, QueryTooLargeError
from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.queries import IN_SERIES, Series

IN_RANGE = "t0 BETWEEN ? AND ? AND t1 >= ?"
WHERE = f"{IN_SERIES} AND {IN_RANGE}"  # params: SeriesSet.scan(start, end)
PAGE_SAMPLES = 65_536  # samples a time page aims at: a few ms of numpy work
_FIRST_WIDTH = 10**9  # ns of the first time page; later pages adapt to the data
Index = npt.NDArray[np.intp]


@dataclass(frozen=True, slots=True)
class SeriesSet:
    """The series of one query, in the order of its answer; `position` maps series ids to
    that order."""

    series: tuple[Series, ...]

    @classmethod
    def of(cls, series: Sequence[Series]) -> SeriesSet:
        return cls(tuple(series))

    def __len__(self) -> int:
        return len(self.series)

    @property
    def ids_json(self) -> str:
        return orjson.dumps([s.id for s in self.series]).decode()

    def scan(self, start: int, end: int) -> tuple[str, int, int, int]:
        """The parameters of WHERE: a block holding samples in [start, end] begins no
        earlier than `start - max_span` of the widest series."""
        widest = max((s.max_span for s in self.series), default=0)
        return (self.ids_json, max(MIN_TIME, start - widest), end, start)

    def position(self, ids: npt.NDArray[np.int64]) -> Index:
        """The position in this set of each series id in `ids`."""
        known = np.asarray([s.id for s in self.series], dtype=np.int64)
        order = np.argsort(known, kind="stable")
        return order[np.searchsorted(known[order], ids)].astype(np.intp)

    def subset(self, keep: Sequence[bool]) -> SeriesSet:
        return SeriesSet(tuple(s for s, k in zip(self.series, keep, strict=True) if k))


@dataclass(slots=True)
class Page:
    """Blocks in (t0, rowid) order. After it, every block with t0 < `frontier` has been
    given: samples before it are final. `frontier` None: every block has been given."""

    frontier: int | None
    series: Index  # per block: its series' position in the set
    kinds: list[str]
    times: list[bytes]
    vals: list[bytes]


def time_pages(
    conn: sqlite3.Connection,
    sset: SeriesSet,
    start: int,
    end: int,
    budget: ReadBudget,
    with_values: bool = True,
) -> Iterator[Page]:
    """The blocks of `sset` touching [start, end], all series together in time order, a page
    of about PAGE_SAMPLES samples at a time (a page is never smaller than the blocks that
    begin at one time). Each page costs one index seek per series and one read of its
    blocks, so the work grows with the data and the number of pages, not with a product of
    signals and blocks."""
    ids, lowest, _, _ = sset.scan(start, end)
    values = "vals" if with_values else "NULL"
    pos, width = lowest, _FIRST_WIDTH
    while True:
        budget.check()
        first = _next_t0(conn, ids, pos, end)
        if first is None:
            return
        last = min(end, first + width - 1)
        rows = conn.execute(
            f"SELECT series_id, t0, rowid, n, kind, times, {values} FROM blocks "
            f"WHERE {IN_SERIES} AND t0 BETWEEN ? AND ? AND t1 >= ?",
            (ids, first, last, start),
        ).fetchall()
        # Sorted here rather than by SQLite, whose sorter would copy every blob once more.
        series, t0, rowid, n, kinds, times, vals = zip(*rows, strict=True) if rows else [()] * 7
        t0s = np.asarray(t0, dtype=np.int64)
        order = np.lexsort((np.asarray(rowid, dtype=np.int64), t0s))
        sizes = np.asarray(n, dtype=np.int64)[order]
        cut, keep = _cut(t0s[order], sizes, budget)
        order = order[:keep]
        frontier = cut if cut is not None else None if last >= end else last + 1
        if keep:
            pick = order.tolist()
            yield Page(
                frontier=frontier,
                series=sset.position(np.asarray(series, dtype=np.int64)[order]),
                kinds=[kinds[i] for i in pick],
                times=[times[i] for i in pick],
                vals=[vals[i] for i in pick],
            )
        if frontier is None:
            return
        if cut is not None:  # the window held too much: the next one is as wide as the taken
            width = max(1, cut - first)
        else:
            taken = int(sizes.sum())
            width = max(1, min(width * 8, width * PAGE_SAMPLES // max(1, taken)))
        pos = frontier


def _next_t0(conn: sqlite3.Connection, ids: str, pos: int, end: int) -> int | None:
    """The smallest block start in [pos, end] over the series (an index seek each)."""
    row = conn.execute(
        "SELECT MIN((SELECT t0 FROM blocks WHERE series_id = j.value AND t0 BETWEEN ? AND ? "
        "ORDER BY t0 LIMIT 1)) FROM json_each(?) AS j",
        (pos, end, ids),
    ).fetchone()
    return None if row[0] is None else int(row[0])


def _cut(
    t0: npt.NDArray[np.int64], sizes: npt.NDArray[np.int64], budget: ReadBudget
) -> tuple[int | None, int]:
    """How many of a window's blocks (by t0, with their sizes) to use now, and where they
    stop: None when all of them are taken, else the block start the page stops before (a
    page stops at a block start once it holds PAGE_SAMPLES samples). A window that holds
    too much costs its rows once, and the next window is made narrower."""
    if t0.size == 0:
        return None, 0
    total = np.cumsum(sizes)
    if int(total[-1]) <= 2 * PAGE_SAMPLES:
        return None, t0.size
    over = int(np.searchsorted(total, PAGE_SAMPLES, side="right"))
    cut = int(np.searchsorted(t0, t0[min(over, t0.size - 1)], side="left"))
    if cut == 0:  # the blocks of the first start time are more than a page: take them all
        cut = int(np.searchsorted(t0, t0[0], side="right"))
    held = int(total[cut - 1])
    if held > budget.max_values:
        raise QueryTooLargeError(
            f"{held:,} values begin at one time; at most {budget.max_values:,} can be read at "
            "once (TWINLINK_HISTORY_QUERY_MAX_VALUES): name fewer `signals`"
        )
    if cut == t0.size:
        return None, cut
    return int(t0[cut]), cut


# A float64 holds every integer below 2^53 exactly.
EXACT_FLOAT = 9_007_199_254_740_992.0


@dataclass(slots=True)
class Kinds:
    """What each series of a set holds in a range (arrays by position in the set), from the
    block summaries alone: one statement for all the series."""

    blocks: npt.NDArray[np.int64]
    samples: npt.NDArray[np.int64]  # of the whole blocks touching the range
    numeric: npt.NDArray[np.bool_]  # a block that is not JSON (text)
    integer: npt.NDArray[np.bool_]  # every block holds int64 values
    big: npt.NDArray[np.bool_]  # an integer block holds a value of 2^53 or more (|v|)

    @property
    def text_only(self) -> npt.NDArray[np.bool_]:
        return (self.blocks > 0) & ~self.numeric


def classify(conn: sqlite3.Connection, sset: SeriesSet, start: int, end: int) -> Kinds:
    n = len(sset)
    kinds = Kinds(
        np.zeros(n, dtype=np.int64),
        np.zeros(n, dtype=np.int64),
        np.zeros(n, dtype=bool),
        np.zeros(n, dtype=bool),
        np.zeros(n, dtype=bool),
    )
    rows = conn.execute(
        "SELECT series_id, COUNT(*), SUM(n), MAX(kind <> 'j'), MIN(kind = 'i'), "
        "MAX(CASE WHEN kind = 'i' THEN MAX(ABS(vmin), ABS(vmax)) ELSE 0 END) "
        f"FROM blocks WHERE {WHERE} GROUP BY series_id",
        sset.scan(start, end),
    ).fetchall()
    if rows:
        table = np.asarray([r[:5] for r in rows], dtype=np.int64)
        at = sset.position(table[:, 0])
        kinds.blocks[at] = table[:, 1]
        kinds.samples[at] = table[:, 2]
        kinds.numeric[at] = table[:, 3] == 1
        kinds.integer[at] = table[:, 4] == 1
        kinds.big[at] = np.asarray([r[5] >= EXACT_FLOAT for r in rows])
    return kinds
