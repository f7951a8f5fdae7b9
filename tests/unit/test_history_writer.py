"""The group-commit writer of history on a real SQLite file in tmp_path (its blocks:
test_history_codec.py)."""

from __future__ import annotations

import asyncio
import contextlib
import sqlite3
import threading
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import orjson
import pytest

from twinlink.domain.errors import TooManySignalsError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.history import SqliteHistory, staging
from twinlink.store.sqlite.history.codec import (
    decode_times,
    decode_values,
)
from twinlink.store.sqlite.history.writer import HistoryWriter

T = 1_704_067_200 * 10**9  # 2024-01-01T00:00:00Z in ns
RECEIVED = T + 10**12


# --- writer helpers ---------------------------------------------------------------------------


def batch(
    times: list[int],
    values: list[dict[str, Value]],
    *,
    twin_id: int = 1,
    stream: str = "telemetry",
    seq: int | None = None,
) -> SampleBatch:
    return SampleBatch(
        twin_id=twin_id,
        twin=f"twin-{twin_id}",
        stream=stream,
        times=times,
        values=values,
        received_ns=RECEIVED,
        seq=seq,
    )


def one(t: int, value: Value, *, signal: str = "x", **kw: Any) -> SampleBatch:
    return batch([t], [{signal: value}], **kw)


@contextlib.contextmanager
def db(path: Path) -> Iterator[sqlite3.Connection]:
    conn = sqlite3.connect(path)
    try:
        yield conn
    finally:
        conn.close()


def rows(path: Path, sql: str, *args: Any) -> list[tuple[Any, ...]]:
    with db(path) as conn:
        return conn.execute(sql, args).fetchall()


def latest(path: Path, twin_id: int = 1, signal: str = "x") -> tuple[int, Any]:
    [(t, value)] = rows(
        path,
        "SELECT l.t, l.value FROM latest l JOIN series s ON s.id = l.series_id "
        "WHERE s.twin_id = ? AND s.signal = ?",
        twin_id,
        signal,
    )
    return t, orjson.loads(value)


def block_count(path: Path) -> int:
    return int(rows(path, "SELECT count(*) FROM blocks")[0][0])


@pytest.fixture(autouse=True)
def blocks_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests look at the blocks each batch makes: no batch is staged (small batches
    make theirs later, test_history_staging.py)."""
    monkeypatch.setattr(staging, "STAGE_BELOW", 0)


@pytest.fixture
def path(tmp_path: Path) -> Path:
    return tmp_path / "data" / "history.db"


@pytest.fixture
async def writer(path: Path) -> AsyncIterator[HistoryWriter]:
    w = HistoryWriter(path)
    await w.open()
    try:
        yield w
    finally:
        await w.close()


# --- writer -----------------------------------------------------------------------------------


async def test_open_creates_the_file_and_schema(path: Path, writer: HistoryWriter) -> None:
    assert path.is_file()
    tables = {r[0] for r in rows(path, "SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert {"series", "blocks", "latest", "ingested"} <= tables
    assert rows(path, "PRAGMA journal_mode") == [("wal",)]
    assert writer.commits == 0


async def test_append_stores_one_block_per_signal(path: Path, writer: HistoryWriter) -> None:
    b = batch(
        [T + 2, T, T + 1],
        [{"x": 3, "s": "c"}, {"x": 1}, {"x": 2.5, "s": "b", "on": True}],
        twin_id=4,
        stream="imu",
    )
    assert await writer.append(b) is True
    assert writer.commits == 1
    series = {
        r[1]: r[0]
        for r in rows(path, "SELECT id, signal FROM series WHERE twin_id = 4 AND stream = 'imu'")
    }
    assert set(series) == {"x", "s", "on"}
    got = {
        r[0]: r[1:]
        for r in rows(
            path,
            "SELECT series_id, t0, t1, n, kind, vmin, vmax, vsum, first_v, last_v, times, vals "
            "FROM blocks",
        )
    }
    x = got[series["x"]]
    assert x[:9] == (T, T + 2, 3, "f", 1.0, 3.0, 6.5, 1, 3)
    assert decode_times(x[9]).tolist() == [T, T + 1, T + 2]
    assert decode_values("f", x[10]).tolist() == [1.0, 2.5, 3.0]
    s = got[series["s"]]
    assert s[:9] == (T + 1, T + 2, 2, "j", None, None, None, "b", "c")
    assert decode_values("j", s[10]).tolist() == ["b", "c"]
    on = got[series["on"]]
    assert on[:9] == (T + 1, T + 1, 1, "b", 1.0, 1.0, 1.0, 1, 1)  # bools stored as 0/1
    assert latest(path, 4, "x") == (T + 2, 3)
    assert latest(path, 4, "s") == (T + 2, "c")
    assert latest(path, 4, "on") == (T + 1, True)


async def test_a_resent_batch_of_a_device_is_stored_once(path: Path, writer: HistoryWriter) -> None:
    b = one(T, 1.0, seq=9)
    assert await writer.append(b, device_id=5) is True
    assert await writer.append(b, device_id=5) is False
    assert block_count(path) == 1
    assert rows(path, "SELECT device_id, seq, at_ns FROM ingested") == [(5, 9, RECEIVED)]
    # another device with the same seq, or the same device with another seq, is new
    assert await writer.append(b, device_id=6) is True
    assert await writer.append(one(T + 1, 2.0, seq=10), device_id=5) is True
    assert block_count(path) == 3


async def test_duplicates_in_the_same_round_are_caught(path: Path, writer: HistoryWriter) -> None:
    b = one(T, 1.0, seq=1)
    results = await asyncio.gather(writer.append(b, 5), writer.append(b, 5), writer.append(b, 5))
    assert list(results) == [True, False, False]
    assert block_count(path) == 1


async def test_batches_without_device_id_or_seq_are_always_stored(
    path: Path, writer: HistoryWriter
) -> None:
    b = one(T, 1.0, seq=3)
    assert await writer.append(b) is True
    assert await writer.append(b) is True
    unnumbered = one(T, 1.0)
    assert await writer.append(unnumbered, device_id=5) is True
    assert await writer.append(unnumbered, device_id=5) is True
    assert block_count(path) == 4
    assert rows(path, "SELECT count(*) FROM ingested") == [(0,)]


async def test_concurrent_appends_share_commits(path: Path, writer: HistoryWriter) -> None:
    n = 50
    results = await asyncio.gather(
        *(writer.append(one(T + i, float(i), seq=i), device_id=1) for i in range(n))
    )
    assert results == [True] * n
    assert 1 <= writer.commits < n
    assert block_count(path) == n
    assert rows(path, "SELECT count(*) FROM series") == [(1,)]
    assert latest(path) == (T + n - 1, float(n - 1))


async def test_sequential_appends_commit_each(writer: HistoryWriter) -> None:
    for i in range(3):
        await writer.append(one(T + i, i))
    assert writer.commits == 3


async def test_latest_keeps_the_greatest_time_when_an_older_batch_arrives_later(
    path: Path, writer: HistoryWriter
) -> None:
    await writer.append(one(T + 10, 10))
    await writer.append(one(T + 5, 5))
    assert latest(path) == (T + 10, 10)
    await writer.append(one(T + 20, "twenty"))
    assert latest(path) == (T + 20, "twenty")


async def test_latest_keeps_the_greatest_time_within_one_round(
    path: Path, writer: HistoryWriter
) -> None:
    await asyncio.gather(
        writer.append(one(T + 10, 10)), writer.append(one(T + 30, 30)), writer.append(one(T, 0))
    )
    assert writer.commits == 1
    assert latest(path) == (T + 30, 30)


async def test_latest_uses_the_last_time_of_an_unsorted_batch(
    path: Path, writer: HistoryWriter
) -> None:
    await writer.append(batch([T + 3, T + 1, T + 2], [{"x": 3}, {"x": 1}, {"x": 2}]))
    assert latest(path) == (T + 3, 3)


async def test_latest_is_kept_per_series(path: Path, writer: HistoryWriter) -> None:
    await writer.append(one(T + 1, 1, twin_id=1))
    await writer.append(one(T + 2, 2, twin_id=2))
    await writer.append(one(T, 0, twin_id=1))
    assert latest(path, 1) == (T + 1, 1)
    assert latest(path, 2) == (T + 2, 2)


async def test_series_max_span_grows_with_the_widest_block(
    path: Path, writer: HistoryWriter
) -> None:
    await writer.append(batch([T, T + 100], [{"x": 1}, {"x": 2}]))
    await writer.append(batch([T + 200, T + 1200], [{"x": 1}, {"x": 2}]))
    await writer.append(batch([T + 2000, T + 2010], [{"x": 1}, {"x": 2}]))
    assert rows(path, "SELECT max_span_ns FROM series") == [(1000,)]


async def test_write_runs_inside_the_group_commit(path: Path, writer: HistoryWriter) -> None:
    def count_blocks(conn: sqlite3.Connection) -> int:
        # sees the batch appended before it in the same (not yet committed) transaction
        assert conn.in_transaction
        conn.execute("INSERT INTO ingested VALUES (77, 1, 0)")
        return int(conn.execute("SELECT count(*) FROM blocks").fetchone()[0])

    results = await asyncio.gather(
        writer.append(one(T, 1)), writer.write(count_blocks), writer.append(one(T + 1, 2))
    )
    assert list(results) == [True, 1, True]
    assert writer.commits == 1
    assert rows(path, "SELECT device_id, seq FROM ingested") == [(77, 1)]


async def test_a_failing_write_fails_only_its_caller(path: Path, writer: HistoryWriter) -> None:
    class Boom(Exception):
        pass

    def failing(conn: sqlite3.Connection) -> None:
        conn.execute("INSERT INTO ingested VALUES (1, 1, 0)")
        raise Boom("no")

    def fine(conn: sqlite3.Connection) -> str:
        conn.execute("INSERT INTO ingested VALUES (2, 2, 0)")
        return "ok"

    results = await asyncio.gather(
        writer.append(one(T, 1)),
        writer.write(failing),
        writer.write(fine),
        writer.append(one(T + 1, 2)),
        return_exceptions=True,
    )
    assert results[0] is True and results[3] is True
    assert isinstance(results[1], Boom) and str(results[1]) == "no"
    assert results[2] == "ok"
    assert writer.commits == 1
    # the failing fn's own changes are undone, everything else is committed
    assert rows(path, "SELECT device_id FROM ingested") == [(2,)]
    assert block_count(path) == 2


async def test_a_write_can_drop_a_twin_and_forget_its_series(
    path: Path, writer: HistoryWriter
) -> None:
    await writer.append(one(T, 1, twin_id=3))

    def drop_twin(conn: sqlite3.Connection) -> None:
        conn.execute("DELETE FROM series WHERE twin_id = 3")
        writer.forget_series(3)

    await writer.write(drop_twin)
    assert block_count(path) == 0  # blocks and latest go with their series
    assert rows(path, "SELECT count(*) FROM latest") == [(0,)]
    assert await writer.append(one(T + 1, 2, twin_id=3)) is True
    assert latest(path, 3) == (T + 1, 2)


async def test_data_survives_close_and_reopen(path: Path) -> None:
    first = HistoryWriter(path)
    await first.open()
    await first.append(one(T, 1, seq=1), device_id=5)
    await first.append(batch([T + 1], [{"x": 2, "y": 3}], seq=2), device_id=5)
    await first.close()
    ids = dict(rows(path, "SELECT signal, id FROM series"))

    second = HistoryWriter(path)
    await second.open()
    try:
        assert await second.append(one(T, 1, seq=1), device_id=5) is False  # still deduped
        assert await second.append(one(T + 5, 9, seq=3), device_id=5) is True
        assert await second.append(one(T + 2, 4, signal="y")) is True
    finally:
        await second.close()
    # the series ids were reloaded, not created again
    assert dict(rows(path, "SELECT signal, id FROM series")) == ids
    assert block_count(path) == 5
    assert rows(path, "SELECT count(*) FROM ingested") == [(3,)]
    assert latest(path) == (T + 5, 9)
    assert latest(path, signal="y") == (T + 2, 4)


async def test_close_stores_what_was_pending(path: Path) -> None:
    writer = HistoryWriter(path)
    await writer.open()
    # the tasks start only once close() yields, after the writer's loop was stopped
    tasks = [asyncio.create_task(writer.append(one(T + i, i))) for i in range(5)]
    await writer.close()
    assert all(task.done() for task in tasks)
    assert [task.result() for task in tasks] == [True] * 5
    assert writer.commits == 1
    assert block_count(path) == 5


async def test_close_during_a_commit_resolves_the_callers_of_that_round(path: Path) -> None:
    writer = HistoryWriter(path)
    await writer.open()
    started, release = threading.Event(), threading.Event()

    def slow(conn: sqlite3.Connection) -> str:
        started.set()
        release.wait(10)
        return "done"

    task = asyncio.create_task(writer.write(slow))
    await asyncio.to_thread(started.wait, 10)
    closing = asyncio.create_task(writer.close())
    await asyncio.sleep(0)  # let close() cancel the writer's loop mid-commit
    release.set()
    await closing
    assert writer.commits == 1  # the round did commit
    try:
        assert task.done()
        assert task.result() == "done"
    finally:
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task


async def test_sqlite_history_delegates_to_its_writer(tmp_path: Path) -> None:
    history = SqliteHistory(tmp_path / "data")
    assert history.path == tmp_path / "data" / "history.db"
    await history.open()
    try:
        assert await history.append(one(T, 1, seq=1), device_id=1) is True
        assert await history.append(one(T, 1, seq=1), device_id=1) is False
        assert await history.write(lambda conn: conn.execute("SELECT 40 + 2").fetchone()[0]) == 42
    finally:
        await history.close()
    assert block_count(history.path) == 1


# --- the limit of signals per stream ----------------------------------------------------------


async def test_a_batch_that_would_give_its_stream_too_many_signals_is_refused_whole(
    path: Path,
) -> None:
    writer = HistoryWriter(path, max_signals_per_stream=3)
    await writer.open()
    try:
        assert await writer.append(batch([T], [{"a": 1, "b": 2}], seq=1), device_id=5)
        refused = batch([T + 1, T + 2], [{"a": 3, "c": 4}, {"d": 5, "e": 6}], seq=2)
        with pytest.raises(TooManySignalsError) as caught:
            await writer.append(refused, device_id=5)
        assert str(caught.value) == (
            "this batch would give stream 'telemetry' of twin 'twin-1' 5 signals "
            "(new: 'c', 'd', 'e'); a stream may have at most 3 (the server's "
            "TWINLINK_MAX_SIGNALS_PER_STREAM). The batch was not stored."
        )
        # nothing of it was stored, not even its seq: sent again within the limit, it is
        assert rows(path, "SELECT signal FROM series ORDER BY signal") == [("a",), ("b",)]
        assert block_count(path) == 2
        assert await writer.append(batch([T + 1], [{"a": 3, "c": 4}], seq=2), device_id=5)
        # known signals are always accepted; another stream counts its own
        assert await writer.append(batch([T + 3], [{"a": 1, "b": 2, "c": 3}]))
        assert await writer.append(batch([T], [{"d": 1, "e": 2, "f": 3}], stream="other"))
        with pytest.raises(TooManySignalsError):
            await writer.append(one(T + 4, 1, signal="d"))
    finally:
        await writer.close()


async def test_a_refused_batch_fails_alone_in_its_round(path: Path) -> None:
    writer = HistoryWriter(path, max_signals_per_stream=2)
    await writer.open()
    try:
        results = await asyncio.gather(
            writer.append(one(T, 1, signal="a")),
            writer.append(batch([T], [{"b": 1, "c": 2}])),  # a, b, c: one too many
            writer.append(one(T, 2, signal="b")),
            return_exceptions=True,
        )
        assert results[0] is True and results[2] is True
        assert isinstance(results[1], TooManySignalsError)
        assert writer.commits == 1
    finally:
        await writer.close()
    # The count is read back from the file: still 2 of 2 after a restart.
    again = HistoryWriter(path, max_signals_per_stream=2)
    await again.open()
    try:
        with pytest.raises(TooManySignalsError, match="3 signals"):
            await again.append(one(T, 1, signal="c"))
    finally:
        await again.close()
    assert rows(path, "SELECT signal FROM series ORDER BY signal") == [("a",), ("b",)]
