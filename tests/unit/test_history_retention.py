"""Deleting history: by age in chunks through the writer, the dedupe record after 7 days,
whole twins, and the background maintenance that runs them."""

from __future__ import annotations

import asyncio
import sqlite3
import time

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from twinlink.domain.samples import SampleBatch
from twinlink.history.maintenance import DAY_NS, HistoryMaintenance
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.history.queries import MAX_TIME, MIN_TIME


def count(history: SqliteHistory, sql: str) -> int:
    conn = sqlite3.connect(history.path)
    try:
        return int(conn.execute(sql).fetchone()[0])
    finally:
        conn.close()


async def values(history: SqliteHistory, twin_id: int = TWIN) -> list[object]:
    page = await history.samples(twin_id, STREAM, None, MIN_TIME, MAX_TIME, 10**6)
    return [v for r in page.rows for v in r["values"].values()]


async def test_delete_before_removes_whole_old_blocks_in_chunks(history: SqliteHistory) -> None:
    await write_column(history, "x", [T + i * S for i in range(100)], list(range(100)), 4)
    await write(history, [(T + 10 * S, {"y": "old"})])
    commits = history.writer.commits
    deleted = await history.delete_before(T + 50 * S, chunk=3)
    assert deleted == 12 + 1  # blocks ending before 50 s, and y's block
    assert history.writer.commits - commits >= 5  # a chunk per commit, plus the latest values
    assert await values(history) == list(range(48, 100))  # the block of 48..51 stays whole
    latest = await history.latest(TWIN, STREAM, None)
    assert list(latest) == ["x"]  # y's newest value was older than the cutoff


async def test_batches_are_forgotten_after_the_cutoff(history: SqliteHistory) -> None:
    for seq, received in enumerate([T, T + S, T + 2 * S]):
        batch = SampleBatch(TWIN, "t", STREAM, [T], [{"x": seq}], received, seq=seq)
        assert await history.append(batch, device_id=1)
    assert await history.forget_ingested_before(T + 2 * S, chunk=1) == 2
    assert count(history, "SELECT count(*) FROM ingested") == 1
    # a forgotten batch resent is stored again; the remembered one is still a duplicate
    assert await history.append(SampleBatch(TWIN, "t", STREAM, [T], [{"x": 0}], T, seq=0), 1)
    assert not await history.append(SampleBatch(TWIN, "t", STREAM, [T], [{"x": 2}], T, seq=2), 1)


async def test_delete_twin_removes_its_series_only(history: SqliteHistory) -> None:
    await write_column(history, "x", [T + i for i in range(50)], list(range(50)), 2)
    await write(history, [(T, {"x": 1})], twin_id=TWIN + 1)
    assert await history.delete_twin(TWIN, chunk=7) == 25
    assert await history.streams(TWIN) == []
    assert count(history, "SELECT count(*) FROM latest") == 1
    assert count(history, f"SELECT count(*) FROM series WHERE twin_id = {TWIN}") == 0
    assert await values(history, TWIN + 1) == [1]
    # the writer forgot the deleted series: new data for that twin id lands in new ones
    await write(history, [(T, {"x": 99})])
    assert await values(history) == [99]


async def test_maintenance_applies_retention_and_forgets_old_batches(
    history: SqliteHistory,
) -> None:
    now = T + 30 * DAY_NS
    await write(history, [(T, {"x": 1})])  # 30 days old
    await write(history, [(now - DAY_NS, {"x": 2})])
    old = SampleBatch(TWIN, "t", STREAM, [now], [{"x": 3}], now - 8 * DAY_NS, seq=1)
    await history.append(old, device_id=1)
    keep_all = HistoryMaintenance(history, retention_days=0, clock=lambda: now)
    assert await keep_all.run_once() == {"blocks": 0, "batches": 1}
    assert await values(history) == [1, 2, 3]
    two_weeks = HistoryMaintenance(history, retention_days=14, clock=lambda: now)
    assert await two_weeks.run_once() == {"blocks": 1, "batches": 0}
    assert await values(history) == [2, 3]


async def test_maintenance_runs_in_the_background_and_deletes_twins(
    history: SqliteHistory,
) -> None:
    await write(history, [(T, {"x": 1})])
    await write(history, [(T, {"x": 2})], twin_id=TWIN + 1)
    maintenance = HistoryMaintenance(history, retention_days=1, every_s=0.01)
    maintenance.start()
    try:
        for _ in range(200):  # the first round runs at once and deletes the 2024 samples
            if not await history.streams(TWIN + 1):
                break
            await asyncio.sleep(0.01)
        assert await history.streams(TWIN + 1) == []
        await write(history, [(time.time_ns(), {"x": 3})], twin_id=TWIN + 2)  # recent
        assert await history.streams(TWIN + 2) != []
        maintenance.twins_deleted([TWIN + 2])
    finally:
        await maintenance.stop()  # waits for the twin's deletion
    assert await history.streams(TWIN + 2) == []
