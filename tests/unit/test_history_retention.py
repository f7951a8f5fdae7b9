"""Deleting history: by age in chunks through the writer, the dedupe record after 7 days,
whole twins, and the background maintenance that runs them."""

from __future__ import annotations

import asyncio
import sqlite3
import time

import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.domain.samples import SampleBatch
from twinlink.history.maintenance import DAY_NS, HistoryMaintenance
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history import SqliteHistory, staging
from twinlink.store.sqlite.history import writer as writer_module


@pytest.fixture(autouse=True)
def blocks_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests count blocks or statements of batches written as blocks: no batch is
    staged (test_history_staging.py covers staged batches)."""
    monkeypatch.setattr(staging, "STAGE_BELOW", 0)


def count(history: SqliteHistory, sql: str) -> int:
    conn = sqlite3.connect(history.path)
    try:
        return int(conn.execute(sql).fetchone()[0])
    finally:
        conn.close()


async def values(history: HistoryStore, twin_id: int = TWIN) -> list[object]:
    page = await history.samples(twin_id, STREAM, None, MIN_TIME, MAX_TIME, 10**6)
    return [v for r in page.rows for v in r["values"].values()]


async def test_delete_before_removes_whole_old_blocks_in_chunks(
    sqlite_history: SqliteHistory,
) -> None:
    await write_column(sqlite_history, "x", [T + i * S for i in range(100)], list(range(100)), 4)
    await write(sqlite_history, [(T + 10 * S, {"y": "old"})])
    commits = sqlite_history.writer.commits
    deleted = await sqlite_history.delete_before(T + 50 * S, chunk=3)
    assert deleted == 12 + 1  # blocks ending before 50 s, and y's block
    # a chunk per commit, plus the latest values
    assert sqlite_history.writer.commits - commits >= 5
    assert await values(sqlite_history) == list(range(48, 100))  # the block of 48..51 stays whole
    latest = await sqlite_history.latest(TWIN, STREAM, None)
    assert list(latest) == ["x"]  # y's newest value was older than the cutoff


async def test_batches_are_forgotten_after_the_cutoff(sqlite_history: SqliteHistory) -> None:
    for seq, received in enumerate([T, T + S, T + 2 * S]):
        batch = SampleBatch(TWIN, "t", STREAM, [T], [{"x": seq}], received, seq=seq)
        assert await sqlite_history.append(batch, device_id=1)
    assert await sqlite_history.forget_ingested_before(T + 2 * S, chunk=1) == 2
    assert count(sqlite_history, "SELECT count(*) FROM ingested") == 1
    # a forgotten batch resent is stored again; the remembered one is still a duplicate
    assert await sqlite_history.append(SampleBatch(TWIN, "t", STREAM, [T], [{"x": 0}], T, seq=0), 1)
    assert not await sqlite_history.append(
        SampleBatch(TWIN, "t", STREAM, [T], [{"x": 2}], T, seq=2), 1
    )


async def test_delete_twin_removes_its_series_only(sqlite_history: SqliteHistory) -> None:
    await write_column(sqlite_history, "x", [T + i for i in range(50)], list(range(50)), 2)
    await write(sqlite_history, [(T, {"x": 1})], twin_id=TWIN + 1)
    assert await sqlite_history.delete_twin(TWIN, chunk=7) == 25
    assert await sqlite_history.streams(TWIN) == []
    assert count(sqlite_history, "SELECT count(*) FROM latest") == 1
    assert count(sqlite_history, f"SELECT count(*) FROM series WHERE twin_id = {TWIN}") == 0
    assert await values(sqlite_history, TWIN + 1) == [1]
    # the writer forgot the deleted series: new data for that twin id lands in new ones
    await write(sqlite_history, [(T, {"x": 99})])
    assert await values(sqlite_history) == [99]


async def test_maintenance_applies_retention_and_forgets_old_batches(
    history: HistoryStore,
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
    history: HistoryStore,
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


# --- the WAL: bounded while deleting, small afterwards -----------------------------------------


def wal_bytes(history: SqliteHistory) -> int:
    wal = history.path.with_name(history.path.name + "-wal")
    return wal.stat().st_size if wal.exists() else 0


async def scattered(history: SqliteHistory, batches: int, signals: int) -> None:
    """Batches of many signals: the blocks of one chunk of deletions then sit on as many
    pages of the index by series as there are blocks (the most WAL a chunk can need)."""
    for i in range(batches):
        await write(history, [(T + i * S, {f"s{j}": float(j) for j in range(signals)})])


async def test_a_retention_run_leaves_the_wal_below_its_limit(
    sqlite_history: SqliteHistory,
) -> None:
    await scattered(sqlite_history, 60, 500)
    await sqlite_history.writer.checkpoint()
    assert sqlite_history.path.stat().st_size > 3 * 2**20  # a database of some MB
    limit = await sqlite_history.write(
        lambda c: c.execute("PRAGMA journal_size_limit").fetchone()[0]
    )
    assert limit == sqlite_history.writer.wal_limit == 16 * 2**20
    maintenance = HistoryMaintenance(sqlite_history, retention_days=1, clock=lambda: T + 2 * DAY_NS)
    assert (await maintenance.run_once())["blocks"] == 60 * 500
    assert wal_bytes(sqlite_history) == 0  # checkpointed and truncated after the run
    assert count(sqlite_history, "SELECT count(*) FROM blocks") == 0


async def test_a_long_read_pauses_retention_rather_than_growing_the_wal(
    sqlite_history: SqliteHistory, monkeypatch: pytest.MonkeyPatch
) -> None:
    await scattered(sqlite_history, 60, 500)
    await sqlite_history.writer.checkpoint()
    sqlite_history.writer.wal_limit = 256 * 1024
    monkeypatch.setattr(writer_module, "WAL_POLL_S", 0.01)
    busy = asyncio.Event()
    paused_at: list[tuple[int, int]] = []  # (WAL bytes, blocks left) at each busy checkpoint
    checkpoint = sqlite_history.writer.checkpoint

    async def watched() -> tuple[int, int, int]:
        answer = await checkpoint()
        if answer[0]:
            paused_at.append(
                (wal_bytes(sqlite_history), count(sqlite_history, "SELECT count(*) FROM blocks"))
            )
            if len(paused_at) >= 3:
                busy.set()
        return answer

    monkeypatch.setattr(sqlite_history.writer, "checkpoint", watched)
    reader = sqlite3.connect(sqlite_history.path)  # an export in the middle of its read
    reader.execute("BEGIN")
    reader.execute("SELECT count(*) FROM blocks").fetchone()
    try:
        deleting = asyncio.create_task(sqlite_history.delete_before(T + 100 * S, chunk=100))
        await asyncio.wait_for(busy.wait(), 30)
    finally:
        reader.rollback()
        reader.close()
    assert await deleting == 60 * 500
    # It waited (no block deleted between the busy checkpoints) with the WAL at the limit
    # plus one chunk; without waiting, 300 chunks of ~100 pages each would have gone there.
    assert paused_at[0][1] == paused_at[-1][1] > 0
    assert paused_at[0][0] < 4 * 2**20
    assert wal_bytes(sqlite_history) <= sqlite_history.writer.wal_limit
