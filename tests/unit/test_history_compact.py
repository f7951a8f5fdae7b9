"""Compaction merges small blocks into large ones without changing what any read returns."""

from __future__ import annotations

import sqlite3
from typing import Any

import pytest

import twinlink.store.sqlite.history as history_module
from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history import SqliteHistory, staging, streams
from twinlink.store.sqlite.history.compact import MAX_SAMPLES, MAX_SPAN_NS, SMALL, plan_runs


@pytest.fixture(autouse=True)
def blocks_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests count blocks or statements of batches written as blocks: no batch is
    staged (test_history_staging.py covers staged batches)."""
    monkeypatch.setattr(staging, "STAGE_BELOW", 0)


def _blocks(history: SqliteHistory, signal: str) -> list[tuple[int, int, int, str]]:
    conn = sqlite3.connect(history.path)
    try:
        return conn.execute(
            "SELECT t0, t1, n, kind FROM blocks JOIN series ON series.id = series_id "
            "WHERE signal = ? ORDER BY t0",
            (signal,),
        ).fetchall()
    finally:
        conn.close()


async def _reads(history: HistoryStore) -> dict[str, object]:
    """What every kind of read answers for the first minute, in comparable form."""
    fns = ["avg", "min", "max", "count", "first", "last"]
    end = T + 60 * S
    shapes = {}
    for method in ("minmax", "lttb"):
        found = await history.downsample(TWIN, STREAM, ["x"], T, end, 100, method)
        shapes[method] = {k: (d.times.tolist(), d.values.tolist()) for k, d in found.items()}
    return {
        "samples": (await history.samples(TWIN, STREAM, None, T, end, 10_000)).rows,
        # Sums are added in another order after a merge: compare averages to 1e-9.
        "aggregate": [
            {
                **row,
                "values": {"x": {**row["values"]["x"], "avg": round(row["values"]["x"]["avg"], 9)}},
            }
            for row in (await history.aggregate(TWIN, STREAM, ["x"], T, end, 7 * S, fns)).rows
        ],
        "downsample": shapes,
        "latest": await history.latest(TWIN, STREAM, None),
        # The merged block's times hash is the sum of its parts': counted the same, unread.
        "streams": await history.streams(TWIN),
    }


def test_runs_group_neighbours_up_to_the_limits() -> None:
    small = [(i, T + i * S, T + i * S, 10) for i in range(5)]
    assert plan_runs(small) == [[0, 1, 2, 3, 4]]
    assert plan_runs(small, max_samples=25) == [[0, 1], [2, 3]]  # the last one stays alone
    big = (99, T + 2 * S, T + 3 * S, SMALL)
    assert plan_runs([*small[:2], big, *small[2:]]) == [[0, 1], [2, 3, 4]]
    spread = [(i, T + i * MAX_SPAN_NS // 2, T + i * MAX_SPAN_NS // 2, 1) for i in range(4)]
    assert plan_runs(spread) == [[0, 1, 2], [3]][:1]
    assert plan_runs([small[0]]) == []


async def test_small_blocks_become_one_and_reads_do_not_change(
    sqlite_history: SqliteHistory,
) -> None:
    times = [T + i * 10_000_000 for i in range(3000)]  # 100 Hz, 30 s
    values = [float((i * 37) % 1000) + i * 1e-6 for i in range(3000)]  # no ties for min/max
    await write_column(sqlite_history, "x", times, values, block=5)
    await write_column(sqlite_history, "n", times, list(range(3000)), block=5)
    before = await _reads(sqlite_history)
    assert len(_blocks(sqlite_history, "x")) == 600
    done = await sqlite_history.compact()
    assert (done.before, done.after) == (1200, 2)
    assert [(b[2], b[3]) for b in _blocks(sqlite_history, "x")] == [(3000, "f")]
    assert [(b[2], b[3]) for b in _blocks(sqlite_history, "n")] == [(3000, "i")]
    assert await _reads(sqlite_history) == before
    assert (await sqlite_history.compact()).before == 0  # nothing new: nothing to do


async def test_merged_blocks_respect_the_sample_limit(sqlite_history: SqliteHistory) -> None:
    count = MAX_SAMPLES * 2 + 500
    times = [T + i * 1_000_000 for i in range(count)]  # 1 kHz
    await write_column(sqlite_history, "x", times, [1.0] * count, block=50)
    await sqlite_history.compact()
    sizes = [b[2] for b in _blocks(sqlite_history, "x")]
    assert sum(sizes) == count and max(sizes) <= MAX_SAMPLES and len(sizes) == 3


async def test_a_merged_block_is_found_by_a_range_query_inside_it(
    sqlite_history: SqliteHistory,
) -> None:
    # The merged block spans more than any block written before: a query for its last
    # second must still find it (series.max_span_ns grows with it, also in the writer's cache).
    times = [T + i * S // 10 for i in range(500)]  # 10 Hz, 50 s, in blocks of 0.4 s
    await write_column(sqlite_history, "x", times, list(range(500)), block=4)
    await sqlite_history.compact()
    # a new batch: the cache must be right
    await write(sqlite_history, [(T + 100 * S, {"x": 1000})])
    page = await sqlite_history.samples(TWIN, STREAM, ["x"], T + 49 * S, T + 49 * S + S // 2, 100)
    assert [row["values"]["x"] for row in page.rows] == list(range(490, 496))  # end included


async def test_equal_times_keep_arrival_order_and_mixed_kinds_merge(
    sqlite_history: SqliteHistory,
) -> None:
    await write(sqlite_history, [(T, {"v": 1})])
    await write(sqlite_history, [(T, {"v": 2.5})])
    await write(sqlite_history, [(T + S, {"v": "text"})])
    await write(sqlite_history, [(T + 2 * S, {"v": True})])
    await sqlite_history.compact()
    assert [(b[2], b[3]) for b in _blocks(sqlite_history, "v")] == [(4, "j")]
    page = await sqlite_history.samples(TWIN, STREAM, ["v"], T, T + 3 * S, 10)
    assert [row["values"]["v"] for row in page.rows] == [1, 2.5, "text", True]


async def test_history_of_twins_that_no_longer_exist_is_swept(history: HistoryStore) -> None:
    from twinlink.history.maintenance import HistoryMaintenance

    await write(history, [(T, {"x": 1})], twin_id=7)
    await write(history, [(T, {"x": 2})], twin_id=8)
    maintenance = HistoryMaintenance(history, retention_days=0)
    assert await maintenance.sweep_orphans(existing={7}) == [8]
    await maintenance.stop()  # waits for the deletions it started
    assert await history.twin_ids() == {7}


async def test_a_merged_block_keeps_the_hash_of_its_times(
    sqlite_history: SqliteHistory, monkeypatch: pytest.MonkeyPatch
) -> None:
    times = [T + i * 10_000_000 for i in range(3000)]
    await write_column(sqlite_history, "x", times, [1.0] * 3000, block=5)  # merged by compaction
    await write_column(sqlite_history, "n", times, list(range(3000)), block=3000)  # left alone
    await sqlite_history.compact()

    def unread(*_: object) -> int:
        raise AssertionError("equal times hashes: nothing to read")

    monkeypatch.setattr(streams, "row_count", unread)
    [stream] = await sqlite_history.streams(TWIN)
    assert (stream["samples"], stream["values"]) == (3000, 6000)


async def test_a_long_series_is_compacted_over_several_rounds(
    sqlite_history: SqliteHistory, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(history_module, "COMPACT_ROUND_SAMPLES", 500)
    rounds = 0
    write = sqlite_history.writer.write

    async def counted(fn: Any) -> Any:
        nonlocal rounds
        rounds += 1
        return await write(fn)

    monkeypatch.setattr(sqlite_history.writer, "write", counted)
    times = [T + i * 10_000_000 for i in range(15_000)]  # 100 Hz, 150 s, in blocks of 100
    await write_column(sqlite_history, "x", times, [float(i) for i in range(15_000)], block=100)
    before = await _reads(sqlite_history)
    done = await sqlite_history.compact()
    assert (done.before, done.after) == (150, 3)  # runs of 60 s
    assert rounds == 3  # a run a round: each is more than 500 samples
    assert await _reads(sqlite_history) == before
