"""Samples of several signals as rows in time order, in constant memory: a k-way merge.

Each signal is read block by block in (t0, rowid) order. Once a block starting at T has been
read, no later block holds a sample before T, so that signal's samples before T are final. The
merge emits, across all signals, the samples before the smallest such frontier, joined into
rows, and reads on from the signal that is furthest behind.

Rows join on (time, occurrence): the k-th sample of a signal at time t goes into the k-th row
at t. Samples of one batch share their times, so they meet in one row; a signal with two
samples at one time gives two rows, and no sample is lost.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Generator
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.store.sqlite.history.codec import decode_times, decode_values
from twinlink.store.sqlite.history.columns import (
    EMPTY_TIMES,
    Times,
    Values,
    clip,
    concat_values,
    merge_sorted,
)
from twinlink.store.sqlite.history.queries import MAX_TIME, MIN_TIME, Series, block_pages

Index = npt.NDArray[np.intp]
Ranks = npt.NDArray[np.int64]
_EMPTY_VALUES: Values = np.empty(0, dtype=object)
# (times, values, frontier) runs of one signal; see `series_chunks`
Chunks = Generator[tuple[Times, Values, int | None], None, None]


@dataclass(slots=True)
class Rows:
    """A run of joined rows: their times and occurrence ranks, and per signal the rows it has
    a value in and those values."""

    times: Times
    ranks: Ranks
    columns: list[tuple[Index, Values]]

    def __len__(self) -> int:
        return int(self.times.size)

    def window(self, lo: int, hi: int) -> Rows:
        columns = []
        for idx, vals in self.columns:
            keep = (idx >= lo) & (idx < hi)
            columns.append((idx[keep] - lo, vals[keep]))
        return Rows(self.times[lo:hi], self.ranks[lo:hi], columns)

    def as_dicts(self, names: list[str]) -> list[dict[str, Any]]:
        rows: list[dict[str, Any]] = [{"time": t, "values": {}} for t in self.times.tolist()]
        for name, (idx, vals) in zip(names, self.columns, strict=True):
            for i, v in zip(idx.tolist(), vals.tolist(), strict=True):
                rows[i]["values"][name] = v
        return rows


def occurrence_ranks(times: Times) -> Ranks:
    """For each sample of a sorted column, how many samples before it share its time."""
    n = times.size
    index = np.arange(n, dtype=np.int64)
    if n == 0:
        return index
    first = np.empty(n, dtype=bool)
    first[0] = True
    np.not_equal(times[1:], times[:-1], out=first[1:])
    return index - np.maximum.accumulate(np.where(first, index, 0))


def join(parts: list[tuple[Times, Values]]) -> Rows:
    """Columns of several signals (each sorted by time) as rows joined on (time, occurrence)."""
    if all(np.array_equal(parts[0][0], t) for t, _ in parts[1:]):
        times = parts[0][0]  # the common case: the signals came in the same batches
        every = np.arange(times.size, dtype=np.intp)
        return Rows(times, occurrence_ranks(times), [(every, v) for _, v in parts])
    ranks = [occurrence_ranks(t) for t, _ in parts]
    all_t = np.concatenate([t for t, _ in parts])
    all_r = np.concatenate(ranks)
    order = np.lexsort((all_r, all_t))
    st, sr = all_t[order], all_r[order]
    new = np.ones(st.size, dtype=bool)
    new[1:] = (st[1:] != st[:-1]) | (sr[1:] != sr[:-1])
    row_of = np.empty(st.size, dtype=np.intp)
    row_of[order] = np.cumsum(new) - 1
    columns, offset = [], 0
    for t, v in parts:
        columns.append((row_of[offset : offset + t.size], v))
        offset += t.size
    return Rows(st[new], sr[new], columns)


def series_chunks(conn: sqlite3.Connection, series: Series, start: int, end: int) -> Chunks:
    """(times, values, frontier) runs of one signal's samples in [start, end], in time order:
    every sample before `frontier` has been given (all of them when it is None)."""
    times, values = EMPTY_TIMES, _EMPTY_VALUES
    for page in block_pages(conn, series, start, end):
        for _rowid, t0, kind, tblob, vblob in page:
            k = int(np.searchsorted(times, t0, side="left")) if times.size else 0
            yield times[:k], values[:k], t0
            times, values = times[k:], values[k:]
            t, v = decode_times(tblob), decode_values(kind, vblob)
            if t.size and t[0] <= end and t[-1] >= start:
                times, values = merge_sorted(times, values, *clip(t, v, start, end))
    yield times, values, None


class _Feed:
    __slots__ = ("chunks", "done", "frontier", "times", "values")

    def __init__(self, chunks: Chunks) -> None:
        self.chunks = chunks
        self.times, self.values = EMPTY_TIMES, _EMPTY_VALUES
        self.frontier: int | None = MIN_TIME  # None: every sample has been given
        self.done = False

    def behind(self) -> int:
        return MAX_TIME if self.frontier is None else self.frontier

    def pull(self) -> None:
        try:
            t, v, self.frontier = next(self.chunks)
        except StopIteration:
            self.done, self.frontier = True, None
            return
        if t.size:
            if self.times.size:
                t, v = np.concatenate([self.times, t]), concat_values([self.values, v])
            self.times, self.values = t, v

    def take_before(self, bound: int | None) -> tuple[Times, Values]:
        k = self.times.size
        if bound is not None and k:
            k = int(np.searchsorted(self.times, bound, side="left"))
        taken = self.times[:k], self.values[:k]
        self.times, self.values = self.times[k:], self.values[k:]
        return taken


def joined_rows(
    conn: sqlite3.Connection, series: list[Series], start: int, end: int
) -> Generator[Rows, None, None]:
    """Rows of the signals' samples in [start, end], in time order, a run at a time."""
    feeds = [_Feed(series_chunks(conn, s, start, end)) for s in series]
    try:
        while True:
            live = [f for f in feeds if not f.done]
            if live:
                min(live, key=_Feed.behind).pull()
            bounds = [f.frontier for f in feeds if f.frontier is not None]
            parts = [f.take_before(min(bounds) if bounds else None) for f in feeds]
            if any(t.size for t, _ in parts):
                yield join(parts)
            if not live:
                return
    finally:
        for feed in feeds:
            feed.chunks.close()


@dataclass(slots=True)
class SamplePage:
    rows: list[dict[str, Any]]
    next_key: tuple[int, int] | None  # (time, occurrence) of the first row not given


def sample_page(
    conn: sqlite3.Connection,
    series: list[Series],
    start: int,
    end: int,
    limit: int,
    after: tuple[int, int] | None = None,
) -> SamplePage:
    """Up to `limit` rows from `start` (or from the row `after` names) to `end`."""
    if after is not None:
        start = max(start, after[0])
    names = [s.signal for s in series]
    rows: list[dict[str, Any]] = []
    chunks = joined_rows(conn, series, start, end)
    try:
        for run in chunks:
            if after is not None:
                skip = int(np.count_nonzero((run.times == after[0]) & (run.ranks < after[1])))
                run, after = run.window(skip, len(run)), None
            room = limit - len(rows)
            if len(run) > room:
                rows.extend(run.window(0, room).as_dicts(names))
                return SamplePage(rows, (int(run.times[room]), int(run.ranks[room])))
            rows.extend(run.as_dicts(names))
    finally:
        chunks.close()
    return SamplePage(rows, None)
