"""Aggregation over epoch-aligned buckets: summaries of whole blocks and decoded samples of
straddling blocks must give the same answers as a plain computation over every sample."""

from __future__ import annotations

import numpy as np
import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from twinlink.domain.history import FUNCTIONS
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history.partials import Partials, sample_partials

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
    series = np.zeros(5, dtype=np.intp)
    p = sample_partials(times, values, series, origin=0, width=5)
    assert p.bucket.tolist() == [0, 1, 2]
    assert p.count.tolist() == [2, 2, 1]
    assert p.low.tolist() == [1.0, -1.0, 7.0] and p.high.tolist() == [3.0, 2.0, 7.0]
    late = sample_partials(times[:1] + 4, values[:1] * 10, series[:1], 0, 5)
    both = Partials.concat([p, late]).reduce()
    assert both.bucket.tolist() == [0, 1, 2]
    assert both.values("last") == [10.0, 2.0, 7.0]  # t=4 is the last in bucket 0
    assert both.values("avg")[0] == pytest.approx(14 / 3)


def test_integer_partials_are_exact_and_sums_do_not_overflow() -> None:
    big = 2**62 + 1
    times = np.array([0, 1, 2, 10], dtype=np.int64)
    values = np.array([big, big, -3, 2**63 - 1], dtype=np.int64)
    p = sample_partials(times, values, np.zeros(4, dtype=np.intp), origin=0, width=5)
    assert p.exact
    assert p.values("sum") == [2 * big - 3, 2**63 - 1]  # Python ints, beyond int64 too
    assert p.values("min") == [-3, 2**63 - 1] and p.values("first") == [big, 2**63 - 1]
    many = np.array([2**63 - 1] * 5, dtype=np.int64)
    over = sample_partials(times[:1].repeat(5), many, np.zeros(5, dtype=np.intp), 0, 5)
    assert over.values("sum") == [5 * (2**63 - 1)]


@pytest.mark.parametrize("block", [1, 3, 10, 64])
@pytest.mark.parametrize("width_s", [1, 4, 30])
async def test_matches_a_plain_computation(history: HistoryStore, block: int, width_s: int) -> None:
    rng = np.random.default_rng(block * 100 + width_s)
    times = (T + np.cumsum(rng.integers(1, 400, 300)) * 10**7).tolist()  # 10 ms steps
    values = rng.normal(size=300).round(3).tolist()
    await write_column(history, "x", times, values, block)
    start, end = times[17] + 1, times[260]
    width = width_s * S
    got = await history.aggregate(TWIN, STREAM, ["x"], start, end, width, ALL)
    assert got.text_only == []
    assert_close(answer(got.rows), expected(times, values, start, end, width))


async def test_late_and_overlapping_blocks(history: HistoryStore) -> None:
    times = [T + i * S // 2 for i in range(40)]
    values = [float(i % 7) for i in range(40)]
    await write_column(history, "x", times[::2], values[::2], 4)  # every other sample first
    await write_column(history, "x", times[1::2], values[1::2], 6)  # the rest arrive late
    got = await history.aggregate(TWIN, STREAM, ["x"], T, T + 30 * S, 3 * S, ALL)
    assert_close(answer(got.rows), expected(times, values, T, T + 30 * S, 3 * S))


async def test_buckets_are_aligned_to_the_epoch(history: HistoryStore) -> None:
    await write_column(history, "x", [T + 7 * S + i * S for i in range(10)], list(range(10)), 10)
    got = await history.aggregate(TWIN, STREAM, ["x"], T, T + 60 * S, 5 * S, ["count", "min"])
    assert [(r["time"] - T) // S for r in got.rows] == [5, 10, 15]
    assert [r["values"]["x"] for r in got.rows] == [
        {"count": 3, "min": 0.0},
        {"count": 5, "min": 3.0},
        {"count": 2, "min": 8.0},
    ]


async def test_signals_share_rows_and_ints_and_bools_count_as_numbers(
    history: HistoryStore,
) -> None:
    await write(history, [(T, {"n": 2, "on": True}), (T + S, {"n": 4, "on": False})])
    await write(history, [(T + 10 * S, {"n": 6})])
    got = await history.aggregate(TWIN, STREAM, None, T, T + 20 * S, 10 * S, ["avg", "sum"])
    assert got.rows == [
        {"time": T, "values": {"n": {"avg": 3.0, "sum": 6}, "on": {"avg": 0.5, "sum": 1.0}}},
        {"time": T + 10 * S, "values": {"n": {"avg": 6.0, "sum": 6}}},
    ]
    sums = [type(v["sum"]) for r in got.rows for v in r["values"].values()]
    assert sums == [int, float, int]  # integers stay integers; bools are numbers


async def test_text_signals_are_reported_and_mixed_batches_keep_their_numbers(
    history: HistoryStore,
) -> None:
    await write(history, [(T, {"mode": "run", "x": 1}), (T + S, {"mode": "idle", "x": "n/a"})])
    await write(history, [(T + 2 * S, {"x": 3})])
    got = await history.aggregate(TWIN, STREAM, None, T, T + 10 * S, 10 * S, ["count", "sum"])
    assert got.text_only == ["mode"]
    assert got.rows == [{"time": T, "values": {"x": {"count": 2, "sum": 4.0}}}]


async def test_an_empty_range_has_no_rows(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1})])
    got = await history.aggregate(TWIN, STREAM, None, T + S, T + 9 * S, S, ALL)
    assert got.rows == [] and got.text_only == []


BIG = 1682921346513461498  # ns since the epoch sent as a value: float64 rounds it


@pytest.mark.parametrize("block", [1, 4, 50])
async def test_integers_above_2_53_stay_exact(history: HistoryStore, block: int) -> None:
    times = [T + i * S for i in range(200)]
    values = [BIG + (i * 7919) % 1000 - 500 for i in range(200)]
    await write_column(history, "n", times, values, block)
    fns = ["min", "max", "first", "last", "sum", "count", "avg"]
    got = await history.aggregate(TWIN, STREAM, ["n"], T, T + 300 * S, 10 * S, fns)
    for row in got.rows:
        part = [
            v for t, v in zip(times, values, strict=True) if row["time"] <= t < row["time"] + 10 * S
        ]
        assert row["values"]["n"] == {
            "min": min(part), "max": max(part), "first": part[0], "last": part[-1],
            "sum": sum(part), "count": len(part), "avg": sum(part) / len(part),
        }  # fmt: skip
        assert all(type(row["values"]["n"][fn]) is int for fn in ("min", "max", "first", "last"))
    assert len(got.rows) == 20


async def test_integer_sums_are_exact_where_block_sums_are_not(history: HistoryStore) -> None:
    # Every value is exact in float64, but the sum of a block of 16 is past 2^53: the stored
    # REAL vsum is rounded, so the block is read instead of summarised.
    values = [2**50 + 2 * i + 1 for i in range(64)]
    await write_column(history, "n", [T + i for i in range(64)], values, 16)
    got = await history.aggregate(TWIN, STREAM, ["n"], T, T + S, S, ["sum", "min", "max"])
    assert got.rows == [
        {"time": T, "values": {"n": {"sum": sum(values), "min": values[0], "max": values[-1]}}}
    ]
    mixed = [(T + 100 + i, {"n": 2**62 + i}) for i in range(4)]  # beyond int64 in total
    await write(history, mixed)
    got = await history.aggregate(TWIN, STREAM, ["n"], T + 100, T + 200, S, ["sum", "max"])
    assert got.rows[0]["values"]["n"] == {"sum": 4 * 2**62 + 6, "max": 2**62 + 3}
