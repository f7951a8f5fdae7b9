"""Streams with many signals (issue 13): samples, export, aggregate and downsample of 2 000 and
20 000 signals equal a brute-force computation, and their work grows with the data, not with
signals times blocks (counted in SQL statements and SQLite VM steps, not timed)."""

from __future__ import annotations

import csv
import io
import random
import sqlite3
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import orjson
import pytest

from tests.unit._history import STREAM, TWIN, S, T, write
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.domain.samples import Value
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history import SqliteHistory, budget, reader, scan, staging

Batch = list[tuple[int, dict[str, Value]]]


class Reference:
    """What the history holds, computed the slow and obvious way from the batches written:
    a signal's samples at one time keep the order of their blocks by (first time, write
    order), and of their places in a block (stable by time); rows join on (time, k)."""

    def __init__(self) -> None:
        self.samples: dict[str, list[tuple[int, int, int, int, Value]]] = {}
        self.batches = 0

    def add(self, rows: Batch) -> None:
        columns: dict[str, list[tuple[int, Value]]] = {}
        for t, values in rows:
            for name, v in values.items():
                columns.setdefault(name, []).append((t, v))
        for name, column in columns.items():
            first = min(t for t, _ in column)
            ordered = sorted(enumerate(column), key=lambda p: p[1][0])
            for place, (_, (t, v)) in enumerate(ordered):
                self.samples.setdefault(name, []).append((t, first, self.batches, place, v))
        self.batches += 1

    def rows(self, names: list[str], start: int = MIN_TIME, end: int = MAX_TIME) -> list[Any]:
        joined: dict[tuple[int, int], dict[str, Value]] = {}
        for name in names:
            seen: dict[int, int] = {}
            for t, *_, v in sorted(self.samples.get(name, [])):
                if start <= t <= end:
                    k = seen[t] = seen.get(t, -1) + 1
                    joined.setdefault((t, k), {})[name] = v
        return [{"time": t, "values": joined[t, k]} for t, k in sorted(joined)]


async def store(history: HistoryStore, ref: Reference, rows: Batch) -> None:
    await write(history, rows)
    ref.add(rows)


@pytest.fixture
def wide(sqlite_history: SqliteHistory) -> SqliteHistory:
    """The history, with the writer's cap on signals per stream out of the way."""
    sqlite_history.writer.max_signals_per_stream = 10**6
    return sqlite_history


async def everything(history: HistoryStore, limit: int = 10**6, **kw: Any) -> list[Any]:
    rows, after = [], None
    while True:
        page = await history.samples(
            TWIN, STREAM, kw.get("signals"), kw.get("start", MIN_TIME), kw.get("end", MAX_TIME),
            limit, after,
        )  # fmt: skip
        rows.extend(page.rows)
        if page.next_key is None:
            return rows
        after = page.next_key


async def exported(history: HistoryStore, fmt: str, **kw: Any) -> bytes:
    signals, start, end = kw.get("signals"), kw.get("start", MIN_TIME), kw.get("end", MAX_TIME)
    _, pieces = await history.export(TWIN, STREAM, signals, start, end, fmt, "ns")
    return b"".join([p async for p in pieces])


def one_batch(n: int, rows: int = 3) -> Batch:
    names = [f"s{i:05d}" for i in range(n)]
    return [
        (T + r * S, {name: (i * 7 + r) if i % 3 else (i + r) / 4 for i, name in enumerate(names)})
        for r in range(rows)
    ]


@pytest.mark.parametrize("n", [2_000, 20_000])
async def test_one_batch_of_many_signals_reads_back_whole(wide: SqliteHistory, n: int) -> None:
    ref = Reference()
    await store(wide, ref, one_batch(n))
    names = sorted(ref.samples)
    want = ref.rows(names)
    assert await everything(wide) == want
    assert [orjson.loads(line) for line in (await exported(wide, "jsonl")).splitlines()] == want
    table = list(csv.reader(io.StringIO((await exported(wide, "csv")).decode())))
    assert table[0] == ["time", *names]
    assert [row[1:4] for row in table[1:]] == [
        ["0.0", "7", "14"],
        ["0.25", "8", "15"],
        ["0.5", "9", "16"],
    ]
    assert [row[1:] for row in table[1:]] == [
        [str(r["values"][name]) for name in names] for r in want
    ]
    streams = await wide.streams(TWIN)
    assert (streams[0]["samples"], streams[0]["values"]) == (3, 3 * n)


@pytest.fixture(autouse=True)
def blocks_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """The reference orders equal times as blocks written batch by batch are read (by the
    block's first time, then arrival); staged batches are joined into blocks in arrival
    order (test_history_staging.py), so none is staged here."""
    monkeypatch.setattr(staging, "STAGE_BELOW", 0)


@pytest.fixture
def small_pages(monkeypatch: pytest.MonkeyPatch) -> None:
    """Pages of a few samples, so that a few hundred samples cross many page frontiers."""
    monkeypatch.setattr(scan, "PAGE_SAMPLES", 16)
    monkeypatch.setattr(scan, "_FIRST_WIDTH", 1)


def random_batches(seed: int, signals: int, batches: int) -> Iterator[Batch]:
    """Batches of a random part of the signals at random times: equal times within and across
    batches, late batches overlapping earlier ones, text and numbers mixed."""
    rng = random.Random(seed)
    names = [f"sig{i}" for i in range(signals)]
    for b in range(batches):
        rows: Batch = []
        base = rng.randint(0, 60)
        for _ in range(rng.randint(1, 9)):
            t = T + (base + rng.randint(0, 12)) * S
            chosen = rng.sample(names, rng.randint(1, min(6, signals)))
            rows.append(
                (t, {c: rng.choice([b, rng.random(), f"x{b}", b % 2 == 0]) for c in chosen})
            )
        yield rows


@pytest.mark.usefixtures("small_pages")
async def test_random_batches_join_like_the_reference(wide: SqliteHistory) -> None:
    ref = Reference()
    for rows in random_batches(seed=13, signals=40, batches=60):
        await store(wide, ref, rows)
    names = sorted(ref.samples)
    want = ref.rows(names)
    assert await everything(wide) == want
    assert await everything(wide, limit=7) == want  # cursors across equal times and pages
    some = names[::3]
    part = {"signals": some, "start": T + 20 * S, "end": T + 50 * S}
    assert await everything(wide, **part) == ref.rows(some, T + 20 * S, T + 50 * S)
    lines = (await exported(wide, "jsonl", **part)).splitlines()
    assert [orjson.loads(line) for line in lines] == ref.rows(some, T + 20 * S, T + 50 * S)
    streams = await wide.streams(TWIN)
    assert streams[0]["samples"] == len(want)
    assert streams[0]["values"] == sum(len(v) for v in ref.samples.values())


def numbers_of(ref: Reference, name: str, start: int, end: int) -> list[tuple[int, float]]:
    """A signal's numeric samples in range, in stored order (bools as 0 and 1)."""
    return [
        (t, float(v))
        for t, *_, v in sorted(ref.samples[name])
        if start <= t <= end and not isinstance(v, str)
    ]


@pytest.mark.usefixtures("small_pages")
async def test_aggregate_and_downsample_of_many_signals(wide: SqliteHistory) -> None:
    ref = Reference()
    rng = random.Random(5)
    for _ in range(30):  # 300 signals, each batch with all of them at 4 times
        times = sorted(T + rng.randint(0, 3000) * S // 10 for _ in range(4))
        await store(
            wide, ref, [(t, {f"v{i}": rng.randint(-50, 50) + i for i in range(300)}) for t in times]
        )
    start, end, width = T + 17 * S, T + 280 * S, 30 * S
    got = await wide.aggregate(
        TWIN, STREAM, None, start, end, width, ["count", "sum", "min", "max", "first", "last"]
    )
    for name in ("v0", "v150", "v299"):
        per: dict[int, list[float]] = {}
        for t, v in numbers_of(ref, name, start, end):
            per.setdefault(t // width * width, []).append(v)
        assert {r["time"]: r["values"][name] for r in got.rows if name in r["values"]} == {
            b: {
                "count": len(v),
                "sum": sum(v),
                "min": min(v),
                "max": max(v),
                "first": v[0],
                "last": v[-1],
            }
            for b, v in per.items()
        }
    assert len(got.rows) == len({t // width for t, _ in numbers_of(ref, "v0", start, end)})
    found = await wide.downsample(TWIN, STREAM, None, start, end, 1000, "minmax")
    assert len(found) == 300
    for name in ("v0", "v299"):
        want = numbers_of(ref, name, start, end)
        assert (
            list(zip(found[name].times.tolist(), found[name].values.tolist(), strict=True)) == want
        )


class Counted:
    """SQL statements and SQLite VM steps (in units of `budget._PROGRESS_EVERY`) of reads."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.statements = 0
        self.steps = 0
        opened = reader.open_read_connection
        over = budget.ReadBudget._over

        def open_counted(path: Path) -> sqlite3.Connection:
            conn = opened(path)
            conn.set_trace_callback(self._statement)
            return conn

        def counted_over(b: budget.ReadBudget) -> int:
            self.steps += 1
            return over(b)

        monkeypatch.setattr(reader, "open_read_connection", open_counted)
        monkeypatch.setattr(budget.ReadBudget, "_over", counted_over)
        monkeypatch.setattr(budget, "_PROGRESS_EVERY", 1_000)

    def _statement(self, _: str) -> None:
        self.statements += 1

    def reset(self) -> tuple[int, int]:
        done = (self.statements, self.steps)
        self.statements = self.steps = 0
        return done


async def work(history: HistoryStore, counted: Counted) -> dict[str, tuple[int, int]]:
    """(statements, VM steps) of each kind of read over the whole stream."""
    out = {}
    counted.reset()
    await exported(history, "jsonl")
    out["export"] = counted.reset()
    await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 100_000)
    out["samples"] = counted.reset()
    await history.aggregate(TWIN, STREAM, None, T, T + 10**4 * S, S, ["avg", "max"])
    out["aggregate"] = counted.reset()
    await history.downsample(TWIN, STREAM, None, T, T + 100 * S, 4, "minmax")
    out["downsample"] = counted.reset()
    await history.streams(TWIN)
    out["streams"] = counted.reset()
    return out


@pytest.mark.parametrize("batches", [1, 20])
async def test_work_grows_with_the_data_not_with_signals_times_blocks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, batches: int
) -> None:
    counted = Counted(monkeypatch)
    found = {}
    for n in (200, 2_000):
        h = SqliteHistory(tmp_path / str(n), "normal")
        h.writer.max_signals_per_stream = 10**6
        await h.open()
        try:
            for b in range(batches):  # every batch: 5 rows of every signal
                rows = [
                    (T + (b * 5 + r) * S, {f"s{i}": float(i + r) for i in range(n)})
                    for r in range(5)
                ]
                await write(h, rows)
            found[n] = await work(h, counted)
        finally:
            await h.close()
    for read, (statements, steps) in found[2_000].items():
        few, some = found[200][read]
        # ten times the signals and values: a few statements more, for more pages of data,
        # never one per signal (2 000 here)...
        assert statements <= few + 10 and statements < 50, (read, found)
        # ... and SQLite work growing with the values, not with signals times blocks
        assert steps <= 15 * max(some, 1), (read, found)
