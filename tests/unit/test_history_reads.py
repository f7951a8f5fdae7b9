"""The history read side on a real SQLite file: streams, latest values, range queries joined
on time, paging, and blocks that overlap in time (late data)."""

from __future__ import annotations

import random
import sqlite3

import numpy as np
import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.domain.errors import NotFoundError
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.history.merge import join, occurrence_ranks


async def all_rows(history: HistoryStore, signals: list[str] | None = None, **kw: int) -> list:
    page = await history.samples(
        TWIN, STREAM, signals, kw.get("start", MIN_TIME), kw.get("end", MAX_TIME), 1_000_000
    )
    assert page.next_key is None
    return page.rows


def test_occurrence_ranks_count_equal_times_before() -> None:
    times = np.array([1, 1, 2, 3, 3, 3, 5], dtype=np.int64)
    assert occurrence_ranks(times).tolist() == [0, 1, 0, 0, 1, 2, 0]
    assert occurrence_ranks(np.empty(0, dtype=np.int64)).tolist() == []


def test_join_pairs_equal_times_and_keeps_every_sample() -> None:
    a = (np.array([1, 2, 2, 4]), np.array([10, 20, 21, 40]))
    b = (np.array([2, 3, 4, 4]), np.array([0.2, 0.3, 0.4, 0.41]))
    rows = join([a, b])
    assert rows.as_dicts(["a", "b"]) == [
        {"time": 1, "values": {"a": 10}},
        {"time": 2, "values": {"a": 20, "b": 0.2}},
        {"time": 2, "values": {"a": 21}},
        {"time": 3, "values": {"b": 0.3}},
        {"time": 4, "values": {"a": 40, "b": 0.4}},
        {"time": 4, "values": {"b": 0.41}},
    ]


async def test_streams_list_signals_with_kind_count_and_times(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1.5, "n": 1, "on": True, "mode": "run"}), (T + S, {"x": 2})])
    await write(history, [(T + 2 * S, {"x": 3})], stream="imu")
    await write(history, [(T, {"x": 1})], twin_id=TWIN + 1)
    streams = await history.streams(TWIN)
    assert [s["name"] for s in streams] == ["imu", STREAM]
    imu, telemetry = streams
    assert (imu["samples"], imu["first"], imu["last"]) == (1, T + 2 * S, T + 2 * S)
    assert (telemetry["samples"], telemetry["values"], telemetry["count"]) == (2, 5, 5)
    assert all(s["values"] == s["count"] for s in telemetry["signals"])
    kinds = {s["name"]: (s["kind"], s["count"]) for s in telemetry["signals"]}
    assert kinds == {
        "mode": ("string", 1),
        "n": ("integer", 1),
        "on": ("bool", 1),
        "x": ("number", 2),
    }
    assert await history.streams(12345) == []


async def test_latest_is_the_newest_value_even_when_an_old_batch_comes_late(
    history: HistoryStore,
) -> None:
    await write(history, [(T + 5 * S, {"x": 5.0, "mode": "run"})])
    await write(history, [(T + S, {"x": 1.0, "mode": "idle"})])  # late
    latest = await history.latest(TWIN, STREAM, None)
    assert latest == {
        "mode": {"time": T + 5 * S, "value": "run"},
        "x": {"time": T + 5 * S, "value": 5.0},
    }
    assert await history.latest(TWIN, STREAM, ["x"]) == {"x": latest["x"]}


async def test_unknown_stream_or_signal_names_what_exists(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1, "y": 2})])
    with pytest.raises(NotFoundError, match=r"no stream 'imu'.*streams: telemetry"):
        await history.latest(TWIN, "imu", None)
    with pytest.raises(NotFoundError, match=r"no signal 'z'.*signals: x, y"):
        await history.samples(TWIN, STREAM, ["x", "z"], MIN_TIME, MAX_TIME, 10)
    with pytest.raises(NotFoundError, match="no history yet"):
        await history.latest(TWIN + 1, STREAM, None)


async def test_rows_join_signals_of_one_batch_and_keep_types(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1.5, "n": 3, "on": False}), (T + S, {"x": 2.5, "s": "a"})])
    assert await all_rows(history) == [
        {"time": T, "values": {"n": 3, "on": False, "x": 1.5}},
        {"time": T + S, "values": {"s": "a", "x": 2.5}},
    ]
    assert await all_rows(history, ["x"], start=T + 1) == [{"time": T + S, "values": {"x": 2.5}}]


async def test_range_bounds_are_inclusive_and_cut_blocks(history: HistoryStore) -> None:
    await write_column(history, "x", [T + i * S for i in range(10)], list(range(10)), block=4)
    rows = await all_rows(history, start=T + 3 * S, end=T + 6 * S)
    assert [r["values"]["x"] for r in rows] == [3, 4, 5, 6]
    assert await all_rows(history, start=T + 20 * S) == []


async def test_overlapping_blocks_merge_in_time_order(history: HistoryStore) -> None:
    await write_column(history, "x", [T + i * S for i in range(0, 20, 2)], list(range(0, 20, 2)), 5)
    await write_column(history, "x", [T + i * S for i in range(1, 20, 2)], list(range(1, 20, 2)), 3)
    rows = await all_rows(history)
    assert [r["values"]["x"] for r in rows] == list(range(20))
    assert [r["time"] for r in rows] == [T + i * S for i in range(20)]
    # a range starting inside an early, long block still finds it (max_span bounds the scan)
    assert [r["values"]["x"] for r in await all_rows(history, start=T + 15 * S)] == [
        15,
        16,
        17,
        18,
        19,
    ]


async def test_equal_times_keep_arrival_order_and_mixed_kinds(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1}), (T + S, {"x": 2})])
    await write(history, [(T + S, {"x": 2.5}), (T + 2 * S, {"x": "three"})])
    rows = await all_rows(history)
    assert [(r["time"] - T) // S for r in rows] == [0, 1, 1, 2]
    values = [r["values"]["x"] for r in rows]
    assert values == [1, 2, 2.5, "three"]
    assert [type(v) for v in values] == [int, int, float, str]


async def test_paging_returns_every_row_once_even_across_equal_times(
    history: HistoryStore,
) -> None:
    rng = random.Random(3)
    expected = []
    for batch in range(30):
        rows = []
        for _ in range(rng.randint(1, 7)):
            t = T + rng.randint(0, 40) * S  # many equal times, batches overlapping
            values = {"a": rng.random()} if rng.random() < 0.5 else {"a": 1.0, "b": batch}
            rows.append((t, values))
        await write(history, rows)
        expected.extend(rows)
    whole = await all_rows(history)
    assert len(whole) >= len(expected)
    assert sorted(r["time"] for r in whole) == [r["time"] for r in whole]
    for limit in (1, 2, 3, 7, 50):
        pages, after = [], None
        while True:
            page = await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, limit, after)
            assert len(page.rows) <= limit
            pages.extend(page.rows)
            if page.next_key is None:
                break
            after = page.next_key
        assert pages == whole, limit
    count = sum(len(v) for _, v in expected)
    assert sum(len(r["values"]) for r in whole) == count


async def test_a_page_stops_at_the_limit_and_names_the_next_row(history: HistoryStore) -> None:
    await write_column(history, "x", [T + i for i in range(10)], list(range(10)), block=3)
    page = await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 4)
    assert [r["values"]["x"] for r in page.rows] == [0, 1, 2, 3]
    assert page.next_key == (T + 4, 0)
    rest = await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 100, page.next_key)
    assert [r["values"]["x"] for r in rest.rows] == [4, 5, 6, 7, 8, 9]
    assert rest.next_key is None


async def test_extent_is_first_and_last_sample(history: HistoryStore) -> None:
    await write_column(history, "x", [T + i * S for i in range(10)], list(range(10)), block=4)
    await write(history, [(T - 5 * S, {"y": 1}), (T + 50 * S, {"y": 2})])
    assert await history.extent(TWIN, STREAM, ["x"]) == (T, T + 9 * S)
    assert await history.extent(TWIN, STREAM, None) == (T - 5 * S, T + 50 * S)


async def samples_and_rows(history: HistoryStore) -> tuple[int, int]:
    [stream] = await history.streams(TWIN)
    return stream["samples"], len(await all_rows(history))


async def test_stream_samples_are_the_rows_of_samples(history: HistoryStore) -> None:
    # 6 472 samples of 11 signals are 6 472 samples (and 71 192 values), not 71 192
    await write(history, [(T + i, {f"s{k}": i * k for k in range(11)}) for i in range(6_472)])
    [stream] = await history.streams(TWIN)
    assert (stream["samples"], stream["values"]) == (6_472, 71_192)
    # a signal sent now and then joins the rows of the others
    await write(history, [(T + i, {"mode": "run"}) for i in range(0, 6_472, 100)])
    assert await samples_and_rows(history) == (6_472, 6_472)
    # values of another batch at times already stored join those rows too
    await write(history, [(T + 7_000, {"a": 1})])
    await write(history, [(T + 7_000, {"b": 2})])
    assert await samples_and_rows(history) == (6_473, 6_473)
    # a second sample of a signal at one time is a row of its own
    await write(history, [(T + 7_000, {"a": 3}), (T + 7_000, {"a": 4})])
    assert await samples_and_rows(history) == (6_475, 6_475)


async def test_stream_samples_of_blocks_written_before_their_times_hash(
    sqlite_history: SqliteHistory,
) -> None:
    await write(sqlite_history, [(T + i, {"x": i, "y": -i}) for i in range(50)])
    await write(sqlite_history, [(T + 100 + i, {"x": i}) for i in range(20)])
    conn = sqlite3.connect(sqlite_history.path)
    try:
        with conn:
            conn.execute("UPDATE blocks SET times_hash = NULL WHERE rowid % 2 = 0")
    finally:
        conn.close()
    assert await samples_and_rows(sqlite_history) == (70, 70)


async def test_an_unknown_signal_of_a_wide_stream_names_a_few_of_its_signals(
    history: HistoryStore,
) -> None:
    await write(history, [(T, {f"s{i:03d}": i for i in range(300)})])
    with pytest.raises(NotFoundError) as refused:
        await history.samples(TWIN, STREAM, ["nope"], MIN_TIME, MAX_TIME, 10)
    assert str(refused.value).endswith("(its signals: s000, s001, s002, s003, s004, s005, "
        "s006, s007, s008, s009, s010, s011, s012, s013, s014, s015, s016, s017, s018, s019 "
        "and 280 more)")  # fmt: skip
