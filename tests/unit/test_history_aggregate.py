"""Aggregation over epoch-aligned buckets: summaries of whole blocks and decoded samples of
straddling blocks must give the same answers as a plain computation over every sample."""

from __future__ import annotations

import numpy as np
import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.history.aggregate import FUNCTIONS, Partials, sample_partials

ALL = list(FUNCTIONS)


def expected(
    times: list[int], values: list[float], start: int, end: int, width: int
) -> dict[int, dict[str, float]]:
    """Every function per bucket start, the slow and obvious way (first/last by time, ties in
    arrival order)."""
    order = sorted(range(len(times)), key=lambda i: times[i])
    out: dict[int, dict[str, float]] = {}
    buckets: dict[int, list[int]] = {}
    for i in order:
        if start <= times[i] <= end:
            buckets.setdefault(times[i] // width * width, []).append(i)
    for b, idx in sorted(buckets.items()):
        v = [float(values[i]) for i in idx]
        out[b] = {
            "avg": sum(v) / len(v),
            "min": min(v),
            "max": max(v),
            "count": len(v),
            "first": v[0],
            "last": v[-1],
            "sum": sum(v),
        }
    return out


def answer(rows: list[dict], signal: str = "x") -> dict[int, dict[str, float]]:
    return {r["time"]: r["values"][signal] for r in rows if signal in r["values"]}


def assert_close(got: dict, want: dict) -> None:
    assert got.keys() == want.keys()
    for b in want:
        for fn in want[b]:
            assert got[b][fn] == pytest.approx(want[b][fn]), (b - T, fn)


def test_sample_partials_reduce_per_bucket() -> None:
    times = np.array([0, 1, 5, 6, 12], dtype=np.int64)
    values = np.array([1.0, 3.0, -1.0, 2.0, 7.0])
    p = sample_partials(times, values, origin=0, width=5)
    assert p.bucket.tolist() == [0, 1, 2]
    assert p.count.tolist() == [2, 2, 1]
    assert p.low.tolist() == [1.0, -1.0, 7.0] and p.high.tolist() == [3.0, 2.0, 7.0]
    both = Partials.concat([p, sample_partials(times[:1] + 4, values[:1] * 10, 0, 5)]).reduce()
    assert both.bucket.tolist() == [0, 1, 2]
    assert both.values("last") == [10.0, 2.0, 7.0]  # t=4 is the last in bucket 0
    assert both.values("avg")[0] == pytest.approx(14 / 3)


@pytest.mark.parametrize("block", [1, 3, 10, 64])
@pytest.mark.parametrize("width_s", [1, 4, 30])
async def test_matches_a_plain_computation(
    history: SqliteHistory, block: int, width_s: int
) -> None:
    rng = np.random.default_rng(block * 100 + width_s)
    times = (T + np.cumsum(rng.integers(1, 400, 300)) * 10**7).tolist()  # 10 ms steps
    values = rng.normal(size=300).round(3).tolist()
    await write_column(history, "x", times, values, block)
    start, end = times[17] + 1, times[260]
    width = width_s * S
    got = await history.aggregate(TWIN, STREAM, ["x"], start, end, width, ALL)
    assert got.text_only == []
    assert_close(answer(got.rows), expected(times, values, start, end, width))


async def test_late_and_overlapping_blocks(history: SqliteHistory) -> None:
    times = [T + i * S // 2 for i in range(40)]
    values = [float(i % 7) for i in range(40)]
    await write_column(history, "x", times[::2], values[::2], 4)  # every other sample first
    await write_column(history, "x", times[1::2], values[1::2], 6)  # the rest arrive late
    got = await history.aggregate(TWIN, STREAM, ["x"], T, T + 30 * S, 3 * S, ALL)
    assert_close(answer(got.rows), expected(times, values, T, T + 30 * S, 3 * S))


async def test_buckets_are_aligned_to_the_epoch(history: SqliteHistory) -> None:
    await write_column(history, "x", [T + 7 * S + i * S for i in range(10)], list(range(10)), 10)
    got = await history.aggregate(TWIN, STREAM, ["x"], T, T + 60 * S, 5 * S, ["count", "min"])
    assert [(r["time"] - T) // S for r in got.rows] == [5, 10, 15]
    assert [r["values"]["x"] for r in got.rows] == [
        {"count": 3, "min": 0.0},
        {"count": 5, "min": 3.0},
        {"count": 2, "min": 8.0},
    ]


async def test_signals_share_rows_and_ints_and_bools_count_as_numbers(
    history: SqliteHistory,
) -> None:
    await write(history, [(T, {"n": 2, "on": True}), (T + S, {"n": 4, "on": False})])
    await write(history, [(T + 10 * S, {"n": 6})])
    got = await history.aggregate(TWIN, STREAM, None, T, T + 20 * S, 10 * S, ["avg", "sum"])
    assert got.rows == [
        {"time": T, "values": {"n": {"avg": 3.0, "sum": 6.0}, "on": {"avg": 0.5, "sum": 1.0}}},
        {"time": T + 10 * S, "values": {"n": {"avg": 6.0, "sum": 6.0}}},
    ]


async def test_text_signals_are_reported_and_mixed_batches_keep_their_numbers(
    history: SqliteHistory,
) -> None:
    await write(history, [(T, {"mode": "run", "x": 1}), (T + S, {"mode": "idle", "x": "n/a"})])
    await write(history, [(T + 2 * S, {"x": 3})])
    got = await history.aggregate(TWIN, STREAM, None, T, T + 10 * S, 10 * S, ["count", "sum"])
    assert got.text_only == ["mode"]
    assert got.rows == [{"time": T, "values": {"x": {"count": 2, "sum": 4.0}}}]


async def test_an_empty_range_has_no_rows(history: SqliteHistory) -> None:
    await write(history, [(T, {"x": 1})])
    got = await history.aggregate(TWIN, STREAM, None, T + S, T + 9 * S, S, ALL)
    assert got.rows == [] and got.text_only == []
