"""Downsampling for plots: min/max per bucket (from summaries and from decoded samples) and
LTTB, checked against plain computations; peaks must survive."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history.downsample import SUMMARIES_FROM, lttb

# The module (the package's `downsample` is its function).
downsampling = importlib.import_module("twinlink.store.sqlite.history.downsample")


def expected_minmax(
    times: list[int], values: list[float], start: int, end: int, points: int
) -> list[tuple[int, float]]:
    buckets = points // 2
    width = -(-(end - start + 1) // buckets)
    per: dict[int, list[tuple[int, float]]] = {}
    for t, v in sorted(zip(times, values, strict=True)):
        if start <= t <= end:
            per.setdefault((t - start) // width, []).append((t, v))
    out: list[tuple[int, float]] = []
    for b in sorted(per):
        low = min(per[b], key=lambda p: p[1])
        high = max(per[b], key=lambda p: p[1])
        out.extend(sorted({low, high}))
    return out


def reference_lttb(x: list[float], y: list[float], threshold: int) -> list[int]:
    """LTTB as published (Steinarsson 2013, the reference JavaScript), for comparison."""
    n = len(x)
    every = (n - 2) / (threshold - 2)
    a, picked = 0, [0]
    for i in range(threshold - 2):
        avg_start, avg_end = int((i + 1) * every) + 1, min(int((i + 2) * every) + 1, n)
        avg_x = sum(x[avg_start:avg_end]) / (avg_end - avg_start)
        avg_y = sum(y[avg_start:avg_end]) / (avg_end - avg_start)
        lo, hi = int(i * every) + 1, int((i + 1) * every) + 1
        areas = [
            abs((x[a] - avg_x) * (y[j] - y[a]) - (x[a] - x[j]) * (avg_y - y[a])) * 0.5
            for j in range(lo, hi)
        ]
        a = lo + areas.index(max(areas))
        picked.append(a)
    return [*picked, n - 1]


def pairs(result: object) -> list[tuple[int, float]]:
    return list(zip(result.times.tolist(), result.values.tolist(), strict=True))  # type: ignore[attr-defined]


def series(n: int, seed: int, step: int = 10**7) -> tuple[list[int], list[float]]:
    rng = np.random.default_rng(seed)
    times = (T + np.cumsum(rng.integers(1, 3, n)) * step).tolist()
    return times, rng.normal(size=n).tolist()


def test_lttb_matches_the_reference_and_keeps_the_ends() -> None:
    rng = np.random.default_rng(1)
    times = np.cumsum(rng.integers(1, 100, 5000)).astype(np.int64)
    values = rng.normal(size=5000)
    for points in (3, 10, 333, 4999):
        keep = lttb(times, values, points)
        x = (times - times[0]).astype(float).tolist()
        assert keep == reference_lttb(x, values.tolist(), points)
        assert len(keep) == points and keep[0] == 0 and keep[-1] == 4999
    assert lttb(times[:5], values[:5], 10) == [0, 1, 2, 3, 4]
    assert lttb(times, values, 2) == [0, 4999]


@pytest.fixture(params=["alone", "together"])
def paths(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """A signal of 4 000 samples is read with signals of few samples (together, from its
    samples) unless it counts as many: then alone, from summaries or sketches."""
    if request.param == "alone":
        monkeypatch.setattr(downsampling, "TOGETHER_FROM", 0)
        monkeypatch.setattr(downsampling, "TOGETHER_FACTOR", 1)
    return str(request.param)


@pytest.mark.parametrize("block", [1, 2, 50, 400])
async def test_minmax_is_each_buckets_min_and_max(
    history: HistoryStore, block: int, paths: str
) -> None:
    times, values = series(4000, block)
    await write_column(history, "x", times, values, block)
    start, end = times[100] - 5, times[3800] + 5
    points = 100  # 50 buckets; small blocks take the summary path, large ones decode
    got = await history.downsample(TWIN, STREAM, ["x"], start, end, points, "minmax")
    assert pairs(got["x"]) == expected_minmax(times, values, start, end, points)
    assert len(got["x"].times) <= points
    takes_summaries = (3700 / block) >= SUMMARIES_FROM * (points // 2)
    assert takes_summaries == (block <= 2)


@pytest.mark.parametrize(("first", "late"), [(1, 3), (700, 900)])
async def test_minmax_with_late_overlapping_blocks(
    history: HistoryStore, first: int, late: int, paths: str
) -> None:
    times, values = series(3000, 5)
    await write_column(history, "x", times[::2], values[::2], first)
    await write_column(history, "x", times[1::2], values[1::2], late)
    start, end = times[0], times[-1]
    got = await history.downsample(TWIN, STREAM, ["x"], start, end, 40, "minmax")
    assert pairs(got["x"]) == expected_minmax(times, values, start, end, 40)


@pytest.mark.parametrize("method", ["minmax", "lttb"])
@pytest.mark.parametrize("block", [3, 1000])
async def test_a_single_spike_survives(
    history: HistoryStore, method: str, block: int, paths: str
) -> None:
    n = 6_000
    times = [T + i * 10**6 for i in range(n)]
    values = [float(np.sin(i / 300)) for i in range(n)]
    values[4_321] = 50.0
    values[777] = -40.0
    await write_column(history, "x", times, values, block)
    got = await history.downsample(TWIN, STREAM, ["x"], times[0], times[-1], 200, method)
    kept = pairs(got["x"])
    assert len(kept) <= 200
    assert (times[4_321], 50.0) in kept and (times[777], -40.0) in kept
    assert kept == sorted(kept)


async def test_few_samples_come_back_whole(history: HistoryStore) -> None:
    times, values = series(30, 9)
    await write_column(history, "x", times, values, 7)
    for method in ("minmax", "lttb"):
        got = await history.downsample(TWIN, STREAM, ["x"], times[0], times[-1], 100, method)
        assert pairs(got["x"]) == list(zip(times, values, strict=True))


async def test_lttb_on_raw_samples_is_exact_lttb(history: HistoryStore) -> None:
    times, values = series(300, 11)
    await write_column(history, "x", times, values, 25)
    got = await history.downsample(TWIN, STREAM, ["x"], times[0], times[-1], 100, "lttb")
    x = [float(t - times[0]) for t in times]
    want = reference_lttb(x, values, 100)
    assert pairs(got["x"]) == [(times[i], values[i]) for i in want]


async def test_text_signals_are_flagged_and_bools_are_numbers(history: HistoryStore) -> None:
    await write(history, [(T + i * S, {"mode": "run", "on": i % 2 == 0}) for i in range(10)])
    got = await history.downsample(TWIN, STREAM, None, T, T + 9 * S, 4, "minmax")
    assert got["mode"].text_only and got["mode"].times.size == 0
    assert not got["on"].text_only
    assert sorted(set(got["on"].values.tolist())) == [0.0, 1.0]


@pytest.mark.parametrize("offset", [0, 1682921346513461498])  # small, and past 2^53
async def test_integer_signals_come_back_as_their_exact_values(
    history: HistoryStore, offset: int, paths: str
) -> None:
    rng = np.random.default_rng(offset % 1000)
    times = (T + np.cumsum(rng.integers(1, 3, 3000)) * 10**7).tolist()
    # neighbours that one float64 cannot tell apart when past 2^53
    values = [offset + int(v) for v in rng.integers(-40, 40, 3000)]
    await write_column(history, "n", times, values, 100)
    start, end = times[10], times[2900]
    got = await history.downsample(TWIN, STREAM, ["n"], start, end, 100, "minmax")
    assert pairs(got["n"]) == expected_minmax(times, values, start, end, 100)  # type: ignore[arg-type]
    assert {type(v) for v in got["n"].values.tolist()} == {int}
    lttb_picks = await history.downsample(TWIN, STREAM, ["n"], start, end, 50, "lttb")
    stored = dict(zip(times, values, strict=True))
    assert all(stored[t] == v for t, v in pairs(lttb_picks["n"]))  # picks are stored samples
    few = await history.downsample(TWIN, STREAM, ["n"], times[0], times[20], 100, "minmax")
    assert pairs(few["n"]) == list(zip(times[:21], values[:21], strict=True))
