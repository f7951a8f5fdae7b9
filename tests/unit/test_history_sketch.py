"""Block sketches (where the extremes of each chunk of a block are) and the min/max downsample
that reads them: exact against plain computations, for blocks from the writer, blocks merged
by compaction, and blocks written before sketches existed (migration 0003)."""

from __future__ import annotations

import sqlite3
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.unit._history import STREAM, TWIN, T, write, write_column
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from tests.unit.test_history_downsample import expected_minmax, pairs, reference_lttb
from twinlink.domain.samples import Value
from twinlink.store.sqlite.db import migrate
from twinlink.store.sqlite.history import SqliteHistory, chunked, extremes, sketch
from twinlink.store.sqlite.history.codec import decode_times, decode_values, encode

MS = 10**6


def expected(
    times: list[int], values: list[float], start: int, end: int, points: int, method: str
) -> list[tuple[int, float]]:
    """What downsample must answer: every sample when there are no more than `points`, else
    min/max per bucket, and for LTTB, LTTB over a min/max preselection of 4 x points."""
    inside = sorted((t, v) for t, v in zip(times, values, strict=True) if start <= t <= end)
    budget = points if method == "minmax" else 4 * points
    picked = inside if len(inside) <= budget else expected_minmax(times, values, start, end, budget)
    if method == "minmax" or len(picked) <= points:
        return picked
    x = [float(t - picked[0][0]) for t, _ in picked]
    return [picked[i] for i in reference_lttb(x, [v for _, v in picked], points)]


def jittered(n: int, seed: int) -> tuple[list[int], list[float]]:
    rng = np.random.default_rng(seed)
    times = T + np.arange(n) * MS + rng.integers(0, MS, n)
    return np.sort(times).tolist(), rng.normal(size=n).round(3).tolist()


def windows(times: list[int]) -> list[tuple[int, int]]:
    """The whole range, ranges cutting blocks and chunks anywhere, and a narrow one."""
    a, b = times[0], times[-1]
    span = b - a
    return [(a, b), (a + span // 7 + 3, b - span // 5), (a - MS, a + span // 3), (b - 50 * MS, b)]


async def check_all(history: SqliteHistory, signal: str, times: list[int], values: Any) -> None:
    floats = [float(v) for v in values]
    for start, end in windows(times):
        for points in (4, 40, 300):
            for method in ("minmax", "lttb"):
                got = await history.downsample(TWIN, STREAM, [signal], start, end, points, method)
                want = expected(times, floats, start, end, points, method)
                assert pairs(got[signal]) == want, (start - T, end - T, points, method)


def block_rows(history: SqliteHistory, signal: str) -> list[tuple[Any, ...]]:
    conn = sqlite3.connect(history.path)
    try:
        return conn.execute(
            "SELECT n, kind, times, vals, tmin, tmax, sketch FROM blocks "
            "JOIN series ON series.id = series_id WHERE signal = ? ORDER BY t0",
            (signal,),
        ).fetchall()
    finally:
        conn.close()


def forget_sketches(history: SqliteHistory, which: str = "1") -> None:
    """Make blocks look written before migration 0003."""
    conn = sqlite3.connect(history.path)
    try:
        conn.execute(f"UPDATE blocks SET tmin = NULL, tmax = NULL, sketch = NULL WHERE {which}")
        conn.commit()
    finally:
        conn.close()


def test_a_sketch_holds_each_chunks_extremes_the_first_of_equals() -> None:
    n = 3 * sketch.CHUNK + 5
    rng = np.random.default_rng(3)
    times = T + np.cumsum(rng.integers(0, 3, n))  # equal times too
    values = rng.integers(0, 3, n).astype(np.float64)  # many equal values
    vmin, vmax, tmin, tmax, blob = sketch.summarize(times, values)
    assert blob is not None and sketch.is_sketch(blob, n) and not sketch.is_sketch(blob, n + 200)
    ints, floats = sketch.columns(blob)
    assert ints.shape == (4, 6)
    for c in range(4):
        part = slice(c * sketch.CHUNK, (c + 1) * sketch.CHUNK)
        t, v = times[part], values[part]
        low, high = int(v.argmin()), int(v.argmax())
        assert list(ints[c, :4]) == [t[0], t[-1], t[low], t[high]]
        assert list(floats[c, 4:]) == [v[low], v[high]]
    assert (vmin, tmin) == (values.min(), times[values.argmin()])
    assert (vmax, tmax) == (values.max(), times[values.argmax()])
    one = sketch.summarize(times[:7], values[:7])
    assert one[4] is None and one[2] == times[int(values[:7].argmin())]
    two = sketch.summarize(times[: 2 * sketch.CHUNK], values[: 2 * sketch.CHUNK])[4]
    assert two is not None and sketch.columns(two)[0].shape == (2, 6)


async def test_writer_and_compaction_store_what_the_samples_give(
    sqlite_history: SqliteHistory,
) -> None:
    times, values = jittered(3000, 1)
    await write_column(sqlite_history, "big", times, values, 1000)
    await write_column(sqlite_history, "small", times, values, 10)
    ints: list[tuple[int, dict[str, Value]]] = [(T, {"ints": i}) for i in range(5)]
    await write(sqlite_history, [*ints, (T + 9, {"on": True})])
    signals = ["big", "small", "ints", "on"]
    assert_stored(sqlite_history, signals)
    await sqlite_history.compact()
    assert [r[0] for r in block_rows(sqlite_history, "small")] == [3000]  # merged by compaction
    assert_stored(sqlite_history, signals)


def assert_stored(history: SqliteHistory, signals: list[str]) -> None:
    """tmin, tmax and the sketch of each block are those of its samples."""
    for signal in signals:
        for n, kind, tblob, vblob, *stored in block_rows(history, signal):
            t, v = decode_times(tblob), decode_values(kind, vblob).astype(np.float64)
            assert stored == list(sketch.summarize(t, v)[2:])
            assert (stored[2] is not None) == (n > sketch.CHUNK)


@pytest.mark.parametrize("block", [129, 1000, 6000])
async def test_minmax_and_lttb_from_sketches_are_exact(
    sqlite_history: SqliteHistory, block: int
) -> None:
    times, values = jittered(20_000, block)
    await write_column(sqlite_history, "x", times, values, block)
    await check_all(sqlite_history, "x", times, values)


async def test_only_chunks_that_may_hold_an_extreme_are_read(
    sqlite_history: SqliteHistory, monkeypatch: pytest.MonkeyPatch
) -> None:
    times, values = jittered(60_000, 2)
    await write_column(sqlite_history, "x", times, values, 10_000)
    read = count_reads(monkeypatch)
    start, end = times[0], times[-1]
    got = await sqlite_history.downsample(TWIN, STREAM, ["x"], start, end, 40, "minmax")
    assert pairs(got["x"]) == expected(times, values, start, end, 40, "minmax")
    assert 0 < read[0] < 60_000 // 20  # 20 buckets of ~23 chunks: a few cut chunks


def count_reads(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    read = [0]
    real: Callable[..., Any] = extremes.read_ranges

    def counting(*args: Any) -> Any:
        found = real(*args)
        read[0] += found[0].size
        return found

    monkeypatch.setattr(chunked, "read_ranges", counting)
    return read


@pytest.mark.parametrize("block", [3, 50, 1000, 4000])
async def test_blocks_written_before_sketches_give_the_same(
    sqlite_history: SqliteHistory, block: int
) -> None:
    times, values = jittered(12_000, block)
    await write_column(sqlite_history, "x", times, values, block)
    forget_sketches(sqlite_history, "rowid % 3 != 0")  # old and new blocks side by side
    await check_all(sqlite_history, "x", times, values)


async def test_equal_extremes_keep_the_earliest(sqlite_history: SqliteHistory) -> None:
    times, _ = jittered(20_000, 4)
    values = [float(v) for v in np.random.default_rng(4).integers(0, 3, len(times))]
    await write_column(sqlite_history, "x", times[:8000], values[:8000], 2)  # summaries
    await write_column(sqlite_history, "x", times[8000:], values[8000:], 3000)  # sketches
    await check_all(sqlite_history, "x", times, values)


async def test_compacted_history_with_a_tail_of_small_and_late_blocks(
    sqlite_history: SqliteHistory,
) -> None:
    times, values = jittered(30_000, 5)
    await write_column(sqlite_history, "x", times[:24_000], values[:24_000], 100)
    await sqlite_history.compact()
    await write_column(sqlite_history, "x", times[24_000:], values[24_000:], 20)
    late_t = [t + 1 for t in times[5000:9000:3]]  # late, overlapping a merged block
    late_v = [v + 0.5 for v in values[5000:9000:3]]
    await write_column(sqlite_history, "x", late_t, late_v, len(late_t))
    every = sorted(zip(times + late_t, values + late_v, strict=True))
    await check_all(sqlite_history, "x", [t for t, _ in every], [v for _, v in every])


async def test_numbers_of_blocks_mixing_text_are_kept(sqlite_history: SqliteHistory) -> None:
    times, values = jittered(9000, 6)
    await write_column(sqlite_history, "x", times[:6000], values[:6000], 3000)
    mixed: list[Any] = ["off" if i % 10 == 0 else v for i, v in enumerate(values[6000:])]
    mixed[1234] = 99.0  # a peak inside a JSON block
    await write_column(sqlite_history, "x", times[6000:], mixed, 3000)
    numeric = [(t, v) for t, v in zip(times, values[:6000] + mixed, strict=True) if v != "off"]
    got = await sqlite_history.downsample(TWIN, STREAM, ["x"], times[0], times[-1], 40, "minmax")
    assert (times[7234], 99.0) in pairs(got["x"])
    want = expected(
        [t for t, _ in numeric], [v for _, v in numeric], times[0], times[-1], 40, "minmax"
    )
    assert pairs(got["x"]) == want


async def test_a_chunk_across_three_buckets_is_read(sqlite_history: SqliteHistory) -> None:
    """A chunk whose samples spread over several buckets (a slow stretch) holds the only
    samples of the buckets in its middle; its own extremes alone do not settle those."""
    rng = np.random.default_rng(7)
    c = sketch.CHUNK
    dense = 78 * c  # chunk 78 of the block is the slow one
    times = [T + i * MS for i in range(dense)]
    times += [times[-1] + (1 + 10 * k) * MS for k in range(c)]
    times += [times[-1] + (1 + k) * MS for k in range(8000)]
    values = rng.uniform(-5, 5, len(times)).round(3).tolist()
    slow = rng.uniform(-0.9, 0.9, c).round(3)
    slow[0], slow[64] = 1.0, -1.0  # its high in its first bucket, its low in a middle one
    values[dense : dense + c] = slow.tolist()
    await write_column(sqlite_history, "x", times, values, len(times))
    start, end = times[0], times[-1]
    got = await sqlite_history.downsample(TWIN, STREAM, ["x"], start, end, 100, "minmax")
    assert pairs(got["x"]) == expected(times, values, start, end, 100, "minmax")


async def test_a_history_file_from_before_migration_0003(tmp_path: Path) -> None:
    path = tmp_path / "history.db"
    conn = sqlite3.connect(path)
    migrate(conn, target=2, folder_name="history/migrations")
    conn.execute("INSERT INTO series VALUES (1, ?, ?, 'x', ?)", (TWIN, STREAM, 10**12))
    times, values = jittered(8000, 8)
    for i in range(0, 4000, 1000):  # as the writer stored blocks then: twelve columns
        b = encode("x", times[i : i + 1000], list[Value](values[i : i + 1000]))
        conn.execute(
            "INSERT INTO blocks VALUES (1, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (b.t0, b.t1, b.n, b.kind, b.vmin, b.vmax, b.vsum, b.first_v, b.last_v, b.times, b.vals),
        )  # fmt: skip
    conn.commit()
    conn.close()
    history = SqliteHistory(tmp_path, "normal")
    await history.open()
    try:
        await check_all(history, "x", times[:4000], values[:4000])
        await write_column(history, "x", times[4000:], values[4000:], 4000)
        assert [r[6] is not None for r in block_rows(history, "x")] == [False] * 4 + [True]
        await check_all(history, "x", times, values)
    finally:
        await history.close()
