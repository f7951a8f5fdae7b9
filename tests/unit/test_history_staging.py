"""Small batches are staged (one row a batch) and moved into column blocks in bulk: every read
sees them as if they had been written as blocks, they are moved when enough wait or after a
while, a crash leaves none behind, and a disk that fails while staging or moving them loses or
mixes up nothing."""

from __future__ import annotations

import asyncio
import random
import sqlite3
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import orjson
import pytest

from tests.unit._faulty import FaultyConnection, wrap_writer_connections
from tests.unit._history import STREAM, TWIN, S, T, write
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.domain.errors import StorageError
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.history import SqliteHistory, staging

DEVICE = 3


def count(path: Path, table: str) -> int:
    conn = sqlite3.connect(path)
    try:
        return int(conn.execute(f"SELECT count(*) FROM {table}").fetchone()[0])
    finally:
        conn.close()


def random_rows(rng: random.Random, n: int, t: int) -> list[tuple[int, dict[str, Value]]]:
    """`n` samples at distinct times from `t` on, values of every kind (a signal's kind
    changes from batch to batch, as a device sending 0 and 0.5 does)."""
    pick: list[Callable[[], Value]] = [
        lambda: rng.randint(-(2**62), 2**62),
        lambda: rng.random(),
        lambda: rng.random() < 0.5,
        lambda: f"s{rng.randint(0, 9)}",
    ]
    names = ["a", "b", "c"]
    return [
        (t + i * 1000, {s: rng.choice(pick)() for s in rng.sample(names, rng.randint(1, 3))})
        for i in range(n)
    ]


async def reads(h: SqliteHistory) -> dict[str, Any]:
    """What every read of the stream answers."""
    page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 100_000)
    _, pieces = await h.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "jsonl", "ns")
    extent = await h.extent(TWIN, STREAM, None)
    assert extent is not None
    numeric = ["a", "b", "c"]
    agg = await h.aggregate(TWIN, STREAM, None, *extent, 50 * S, ["count", "min", "max", "last"])
    down = await h.downsample(TWIN, STREAM, None, *extent, 40, "minmax")
    streams = await h.streams(TWIN)
    for s in streams:
        for sig in s["signals"]:
            sig.pop("count", None)
    return {
        "rows": page.rows,
        "export": [orjson.loads(line) async for piece in pieces for line in piece.splitlines()],
        "latest": await h.latest(TWIN, STREAM, None),
        "extent": extent,
        "aggregate": (agg.rows, agg.text_only),
        "downsample": {k: (v.times.tolist(), v.values.tolist()) for k, v in down.items()},
        "streams": streams,
        "signals": numeric,
    }


async def test_every_read_sees_staged_batches_as_blocks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = random.Random(4)
    batches = [
        random_rows(rng, rng.randint(1, 12), T + k * 7 * S + rng.randint(0, 3) * S)
        for k in range(300)
    ]
    answers = []
    for stage_below in (staging.STAGE_BELOW, 0):  # staged, and every batch a block at once
        monkeypatch.setattr(staging, "STAGE_BELOW", stage_below)
        h = SqliteHistory(tmp_path / str(stage_below), "normal")
        await h.open()
        try:
            most = 0
            for rows in batches:
                await write(h, rows)
                most = max(most, h.writer.staged(TWIN))
            assert (most > 0) == bool(stage_below)  # small batches wait as rows of their own
            answers.append(await reads(h))
            assert h.writer.staged() == 0  # the reads moved them
        finally:
            await h.close()
    assert answers[0] == answers[1]


async def test_staged_batches_are_one_row_each_until_moved(sqlite_history: SqliteHistory) -> None:
    for k in range(5):
        await write(sqlite_history, [(T + k * S, {"x": k, "y": float(k)})])
    assert count(sqlite_history.path, "staged") == 5
    assert count(sqlite_history.path, "blocks") == 0
    assert sqlite_history.writer.staged(TWIN) == 5
    await sqlite_history.settle(TWIN)
    assert count(sqlite_history.path, "staged") == 0
    assert count(sqlite_history.path, "blocks") == 2  # a block per signal for all five batches
    latest = await sqlite_history.latest(TWIN, STREAM, None)
    assert latest == {"x": {"time": T + 4 * S, "value": 4}, "y": {"time": T + 4 * S, "value": 4.0}}


async def test_equal_times_keep_arrival_order(sqlite_history: SqliteHistory) -> None:
    for value in (3, 1, 2):
        await write(sqlite_history, [(T, {"x": value})])
    page = await sqlite_history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
    assert [r["values"]["x"] for r in page.rows] == [3, 1, 2]


async def test_a_large_batch_after_staged_ones_keeps_their_order(
    sqlite_history: SqliteHistory,
) -> None:
    await write(sqlite_history, [(T, {"x": "first"})])
    await write(sqlite_history, [(T + i, {"x": f"big{i}"}) for i in range(20)])  # a block at once
    assert count(sqlite_history.path, "staged") == 0  # the twin's staged batch went first
    page = await sqlite_history.samples(TWIN, STREAM, None, T, T, 10)
    assert [r["values"]["x"] for r in page.rows] == ["first", "big0"]


async def test_batches_far_apart_in_time_stay_apart_for_retention(
    sqlite_history: SqliteHistory,
) -> None:
    day = 86_400 * S
    await write(sqlite_history, [(T, {"x": 1})])
    await write(sqlite_history, [(T + 10 * day, {"x": 2})])  # the same kind, ten days later
    await sqlite_history.settle(TWIN)
    assert count(sqlite_history.path, "blocks") == 2
    await sqlite_history.delete_before(T + day)
    page = await sqlite_history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
    assert page.rows == [{"time": T + 10 * day, "values": {"x": 2}}]


async def test_a_resent_staged_batch_is_stored_once(sqlite_history: SqliteHistory) -> None:
    batch = SampleBatch(TWIN, "twin", STREAM, [T], [{"x": 1.5}], T, seq=9)
    assert await sqlite_history.append(batch, DEVICE) is True
    assert await sqlite_history.append(batch, DEVICE) is False
    await sqlite_history.settle(None)
    assert await sqlite_history.append(batch, DEVICE) is False  # moved into blocks: still known
    page = await sqlite_history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
    assert page.rows == [{"time": T, "values": {"x": 1.5}}]


async def test_they_are_moved_after_a_while_without_a_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(staging, "FLUSH_AFTER_S", 0.05)
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    try:
        await write(h, [(T, {"x": 1})])
        await _until(lambda: h.writer.staged() == 0)
        assert count(h.path, "blocks") == 1
    finally:
        await h.close()


async def test_they_are_moved_when_many_wait(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(staging, "FLUSH_ROWS", 10)
    monkeypatch.setattr(staging, "FLUSH_ROUND_ROWS", 4)  # in several rounds
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    try:
        for k in range(10):
            await write(h, [(T + k, {"x": k})])
        await write(h, [(T + 10, {"x": 10})])  # the round after the tenth moves them
        await _until(lambda: h.writer.staged() <= 1)
        assert count(h.path, "staged") <= 1
    finally:
        await h.close()


async def test_a_twin_with_many_is_moved_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(staging, "TWIN_FLUSH_ROWS", 5)
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    try:
        await write(h, [(T, {"x": 0})], twin_id=TWIN + 1)  # a quiet twin: it waits
        for k in range(6):
            await write(h, [(T + k, {"x": k})])
        await write(h, [(T + 6, {"x": 6})])
        await _until(lambda: h.writer.staged(TWIN) <= 1)
        assert h.writer.staged(TWIN + 1) == 1
    finally:
        await h.close()


async def test_a_stop_moves_them_and_a_crash_leaves_them_for_the_next_start(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    await write(h, [(T, {"x": 1})])
    await h.close()
    assert count(h.path, "staged") == 0 and count(h.path, "blocks") == 1

    async def crash() -> None:  # as a killed process: nothing moved at the end
        return None

    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    monkeypatch.setattr(h.writer, "_flush_at_close", crash)
    await write(h, [(T + S, {"x": 2})])
    await h.close()
    assert count(h.path, "staged") == 1
    monkeypatch.undo()
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    try:
        assert h.writer.staged(TWIN) == 1
        page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
        assert [r["values"]["x"] for r in page.rows] == [1, 2]
    finally:
        await h.close()


async def test_deleting_a_twin_deletes_its_staged_batches(sqlite_history: SqliteHistory) -> None:
    await write(sqlite_history, [(T, {"x": 1})])
    await write(sqlite_history, [(T, {"x": 2})], twin_id=TWIN + 1)
    await sqlite_history.delete_twin(TWIN)
    assert sqlite_history.writer.staged(TWIN) == 0
    await write(sqlite_history, [(T + S, {"x": 3})])  # a new series for the twin made again
    page = await sqlite_history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
    assert page.rows == [{"time": T + S, "values": {"x": 3}}]
    other = await sqlite_history.samples(TWIN + 1, STREAM, None, MIN_TIME, MAX_TIME, 10)
    assert other.rows == [{"time": T, "values": {"x": 2}}]


# -- a failing disk -----------------------------------------------------------------------


@pytest.fixture
def faulty(monkeypatch: pytest.MonkeyPatch) -> list[FaultyConnection]:
    """The writer's connections, each wrapped in a FaultyConnection (disarmed)."""
    return wrap_writer_connections(monkeypatch)


def one(signal: str, value: float, seq: int) -> SampleBatch:
    return SampleBatch(TWIN, "twin", STREAM, [T + seq * S], [{signal: value}], T, seq=seq)


async def _fail_at(path: Path, faulty: list[FaultyConnection], at: int, whole: bool) -> bool:
    """Staged batches of new signals and a move of staged rows, failing at statement `at`;
    what failed is sent (or moved) again. True when the fault fired."""
    h = SqliteHistory(path, "normal")
    await h.open()
    conn = faulty[-1]
    try:
        assert await h.append(one("w", 1.0, 1), DEVICE)
        conn.arm(at, whole)
        sends: list[Callable[[], Awaitable[Any]]] = [
            lambda: h.append(one("A", 2.0, 2), DEVICE),
            lambda: h.append(one("B", 3.0, 3), DEVICE),
            lambda: h.writer.write(h.writer.flush_staged),
        ]
        results = await asyncio.gather(*(s() for s in sends), return_exceptions=True)
        fired = conn.fired
        conn.disarm()
        for send, result in zip(sends, results, strict=True):
            if isinstance(result, BaseException):
                assert isinstance(result, StorageError), repr(result)
                await send()
        assert await h.append(one("C", 4.0, 4), DEVICE)
        assert await h.append(one("A", 2.0, 2), DEVICE) is False
        page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
        assert page.rows == [
            {"time": T + k * S, "values": {name: value}}
            for k, name, value in [(1, "w", 1.0), (2, "A", 2.0), (3, "B", 3.0), (4, "C", 4.0)]
        ]
        assert h.writer.staged() == 0 and count(h.path, "staged") == 0
    finally:
        await h.close()
    return fired


async def test_reads_go_on_without_staged_batches_while_the_disk_is_full(
    tmp_path: Path, faulty: list[FaultyConnection]
) -> None:
    h = SqliteHistory(tmp_path, "normal")
    await h.open()
    try:
        await write(h, [(T, {"x": 1})])
        await h.settle(TWIN)
        await write(h, [(T + S, {"x": 2})])  # staged
        faulty[-1].arm(at=1, whole=True)  # the move of it fails, as on a full disk
        page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
        assert faulty[-1].fired
        assert page.rows == [{"time": T, "values": {"x": 1}}]  # an answer, without it
        faulty[-1].disarm()
        page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10)
        assert [r["values"]["x"] for r in page.rows] == [1, 2]
    finally:
        await h.close()


@pytest.mark.parametrize("whole", [False, True], ids=["statement", "transaction"])
async def test_a_fault_while_staging_or_moving_loses_or_mixes_up_nothing(
    tmp_path: Path, faulty: list[FaultyConnection], whole: bool
) -> None:
    at = 0
    while await _fail_at(tmp_path / str(at + 1), faulty, at + 1, whole):
        at += 1
    assert at > 10, f"the round had only {at} statements"


async def _until(condition: Callable[[], bool], timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "not within the deadline"
        await asyncio.sleep(0.01)
