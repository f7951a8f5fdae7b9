"""Samples of several signals as rows in time order, in constant memory.

The blocks of all the signals come in time pages (scan.py): after a page, every block that
starts before its frontier has been read, so every sample before the frontier is final. Each
page's final samples (with those held back from earlier pages) are joined into rows with a
few numpy sorts over all of them at once; the rest waits for the next page. The work is the
same per sample whatever the number of signals: no step looks at every signal.

Rows join on (time, occurrence): the k-th sample of a signal at time t goes into the k-th row
at t. Samples of one batch share their times, so they meet in one row; a signal with two
samples at one time gives two rows, and no sample is lost. A signal's samples at one time
keep the order of their blocks by (t0, rowid), and of their places in a block.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Generator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import orjson

from twinlink.domain.history import SamplePage
from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.codec import TIME_DTYPE, VALUE_DTYPES
from twinlink.store.sqlite.history.columns import EMPTY_TIMES, Times, Values
from twinlink.store.sqlite.history.queries import Series
from twinlink.store.sqlite.history.scan import Page, SeriesSet, time_pages

Index = npt.NDArray[np.intp]
Ranks = npt.NDArray[np.int64]
_EMPTY_INDEX: Index = np.empty(0, dtype=np.intp)


@dataclass(slots=True)
class Samples:
    """Samples of several signals, in block order: time, the signal's position, value."""

    times: Times
    series: Index
    values: Values  # Python objects (int, float, bool, str), so each keeps its type

    def __len__(self) -> int:
        return int(self.times.size)

    @classmethod
    def empty(cls) -> Samples:
        return cls(EMPTY_TIMES, _EMPTY_INDEX, np.empty(0, dtype=object))

    def take(self, which: npt.NDArray[Any]) -> Samples:
        return Samples(self.times[which], self.series[which], self.values[which])

    @classmethod
    def concat(cls, parts: Sequence[Samples]) -> Samples:
        return cls(
            np.concatenate([p.times for p in parts]),
            np.concatenate([p.series for p in parts]),
            np.concatenate([p.values for p in parts]),
        )


@dataclass(slots=True)
class Rows:
    """A run of joined rows: per row its time, occurrence rank and where its values start;
    per value its signal's position and the value, row after row, by signal position."""

    times: Times
    ranks: Ranks
    starts: Index  # len(rows) + 1 offsets into series/values
    series: Index
    values: Values

    def __len__(self) -> int:
        return int(self.times.size)

    @property
    def value_count(self) -> int:
        return int(self.series.size)

    def window(self, lo: int, hi: int) -> Rows:
        a, b = int(self.starts[lo]), int(self.starts[hi])
        return Rows(
            self.times[lo:hi],
            self.ranks[lo:hi],
            self.starts[lo : hi + 1] - a,
            self.series[a:b],
            self.values[a:b],
        )

    def as_dicts(self, names: Sequence[str]) -> list[dict[str, Any]]:
        keys = np.asarray(names, dtype=object)[self.series].tolist()
        values = self.values.tolist()
        bounds = self.starts.tolist()
        return [
            {"time": t, "values": dict(zip(keys[a:b], values[a:b], strict=True))}
            for t, a, b in zip(self.times.tolist(), bounds, bounds[1:], strict=False)
        ]


def occurrence_ranks(times: Times) -> Ranks:
    """For each sample of a sorted column, how many samples before it share its time."""
    return _ranks(times != np.roll(times, 1) if times.size else np.empty(0, dtype=bool))


def _ranks(new: npt.NDArray[np.bool_]) -> Ranks:
    """Per element, how many elements before it since the last `new` one."""
    index = np.arange(new.size, dtype=np.int64)
    if new.size == 0:
        return index
    new = new.copy()
    new[0] = True
    return index - np.maximum.accumulate(np.where(new, index, 0))


def join_samples(s: Samples) -> Rows:
    """Samples (all of them final) as rows joined on (time, occurrence)."""
    n = len(s)
    if n == 0:
        return Rows(EMPTY_TIMES, EMPTY_TIMES, np.zeros(1, dtype=np.intp), _EMPTY_INDEX, s.values)
    by_signal = np.lexsort((s.times, s.series))  # stable: equal times keep block order
    t, sig = s.times[by_signal], s.series[by_signal]
    new = np.empty(n, dtype=bool)
    new[0] = True
    np.not_equal(t[1:], t[:-1], out=new[1:])
    new[1:] |= sig[1:] != sig[:-1]
    occurrence = _ranks(new)
    by_row = np.lexsort((sig, occurrence, t))
    t, occurrence, sig = t[by_row], occurrence[by_row], sig[by_row]
    first = np.empty(n, dtype=bool)
    first[0] = True
    np.not_equal(t[1:], t[:-1], out=first[1:])
    first[1:] |= occurrence[1:] != occurrence[:-1]
    starts = np.flatnonzero(first)
    return Rows(
        t[starts],
        occurrence[starts],
        np.append(starts, n).astype(np.intp),
        sig,
        s.values[by_signal[by_row]],
    )


def join(parts: Sequence[tuple[Times, Values]]) -> Rows:
    """Columns of several signals (each in time order) as rows joined on (time, occurrence)."""
    values = np.empty(sum(t.size for t, _ in parts), dtype=object)
    values[:] = [v for _, vs in parts for v in np.asarray(vs).tolist()]
    return join_samples(
        Samples(
            np.concatenate([t for t, _ in parts]).astype(TIME_DTYPE),
            np.repeat(np.arange(len(parts), dtype=np.intp), [t.size for t, _ in parts]),
            values,
        )
    )


def page_samples(page: Page, start: int, end: int) -> Samples:
    """The samples of a page's blocks in [start, end], in block order."""
    sizes = np.fromiter((len(t) // 8 for t in page.times), np.intp, len(page.times))
    times = np.frombuffer(b"".join(page.times), dtype=TIME_DTYPE)
    series = np.repeat(page.series, sizes)
    values = np.empty(times.size, dtype=object)
    kinds = set(page.kinds)
    if len(kinds) == 1:
        values[:] = _decode(next(iter(kinds)), page.vals)
    else:  # each kind in one piece, scattered to its blocks' places
        kind_of = np.asarray(page.kinds)
        for kind in kinds:
            blocks = kind_of == kind
            values[np.repeat(blocks, sizes)] = _decode(
                kind, [v for v, b in zip(page.vals, blocks.tolist(), strict=True) if b]
            )
    keep = (times >= start) & (times <= end)
    if keep.all():
        return Samples(times, series, values)
    return Samples(times[keep], series[keep], values[keep])


def _decode(kind: str, blobs: list[bytes]) -> list[Any]:
    if kind == "j":
        return [v for blob in blobs for v in orjson.loads(blob)]
    array = np.frombuffer(b"".join(blobs), dtype=VALUE_DTYPES[kind])
    return (array.astype(bool) if kind == "b" else array).tolist()  # type: ignore[no-any-return]


def joined_rows(
    conn: sqlite3.Connection, series: list[Series], start: int, end: int, budget: ReadBudget
) -> Generator[Rows, None, None]:
    """Rows of the signals' samples in [start, end], in time order, a page at a time."""
    held = Samples.empty()
    for page in time_pages(conn, SeriesSet.of(series), start, end, budget):
        samples = page_samples(page, start, end)
        if len(held):
            samples = Samples.concat([held, samples])  # held ones come from earlier blocks
        if page.frontier is None:
            final, held = samples, Samples.empty()
        else:
            early = samples.times < page.frontier
            final, held = samples.take(early), samples.take(~early)
        if len(final):
            yield join_samples(final)
        budget.check()
    if len(held):
        yield join_samples(held)


def sample_page(
    conn: sqlite3.Connection,
    series: list[Series],
    start: int,
    end: int,
    limit: int,
    after: tuple[int, int] | None,
    budget: ReadBudget,
) -> SamplePage:
    """Up to `limit` rows from `start` (or from the row `after` names) to `end`; fewer when
    they would hold more values than the budget allows (at least one row)."""
    if after is not None:
        start = max(start, after[0])
    names = [s.signal for s in series]
    rows: list[dict[str, Any]] = []
    room_values = budget.max_values
    chunks = joined_rows(conn, series, start, end, budget)
    try:
        for run in chunks:
            if after is not None:
                skip = int(np.count_nonzero((run.times == after[0]) & (run.ranks < after[1])))
                run, after = run.window(skip, len(run)), None
            per_row = np.cumsum(np.diff(run.starts))
            fits = int(np.searchsorted(per_row, room_values, side="right"))
            take = min(limit - len(rows), max(fits, 0 if rows else 1))
            if take < len(run):
                rows.extend(run.window(0, take).as_dicts(names))
                return SamplePage(rows, (int(run.times[take]), int(run.ranks[take])))
            rows.extend(run.as_dicts(names))
            room_values -= run.value_count
    finally:
        chunks.close()
    return SamplePage(rows, None)
