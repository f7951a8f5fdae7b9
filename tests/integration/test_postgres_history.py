"""What the PostgreSQL history store must do beyond the tests every backend runs
(test_postgres_history_*.py): a resent batch is stored once, also when two nodes store it at
the same time; int64 values stay exact at their limits; partitions are made for any time,
before the epoch and at the end of int64 too; retention drops whole partitions; reads keep to
their budget; a connection the server cuts is a StorageError, and the store goes on; an
export over many pages is the SQLite backend's, byte for byte."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path

import asyncpg
import pytest

from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.unit._history import STREAM, TWIN, S, T, write
from twinlink.domain.errors import StorageError, TooManySignalsError
from twinlink.domain.history import (
    MAX_TIME,
    MIN_TIME,
    QueryTimeoutError,
    QueryTooLargeError,
    SamplePage,
)
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.history import HistoryStore
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history import PostgresHistory, ReadLimits, export, partitions
from twinlink.store.postgres.history.budget import reading
from twinlink.store.sqlite.history import SqliteHistory

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]


@pytest.fixture
async def db(postgres_dsn: str) -> AsyncIterator[PostgresDatabase]:
    database = PostgresDatabase(postgres_dsn)
    await database.open()
    try:
        yield database
    finally:
        await database.close()


def batch(seq: int, times: list[int], twin_id: int = TWIN) -> SampleBatch:
    return SampleBatch(
        twin_id, f"twin{twin_id}", STREAM, times, [{"x": i} for i in range(len(times))], T,
        seq=seq,
    )  # fmt: skip


async def all_values(history: PostgresHistory) -> list[tuple[int, int]]:
    page = await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10_000)
    return [(row["time"], row["values"]["x"]) for row in page.rows]


async def test_a_resent_batch_is_stored_once(db: PostgresDatabase) -> None:
    history = PostgresHistory(db)
    assert await history.append(batch(1, [T, T + S]), device_id=5)
    assert not await history.append(batch(1, [T, T + S]), device_id=5)
    assert await history.append(batch(1, [T, T + S]), device_id=6)  # another device's seq 1
    assert await history.append(batch(2, [T + 2 * S]), device_id=5)
    assert await all_values(history) == [(T, 0), (T, 0), (T + S, 1), (T + S, 1), (T + 2 * S, 0)]
    [stream] = await history.streams(TWIN)
    assert stream["values"] == 5  # the summary counted the resend once too


async def test_two_nodes_storing_one_batch_at_once_store_it_once(postgres_dsn: str) -> None:
    nodes = [PostgresDatabase(postgres_dsn) for _ in range(2)]
    for node in nodes:
        await node.open()
    try:
        stores = [PostgresHistory(node) for node in nodes]
        for seq in range(20):
            sent = batch(seq, [T + seq * S + i for i in range(50)])
            stored = await asyncio.gather(*(s.append(sent, device_id=9) for s in stores))
            assert sorted(stored) == [False, True]
        assert len(await all_values(stores[0])) == 20 * 50
    finally:
        for node in nodes:
            await node.close()


async def test_int64_values_stay_exact_at_their_limits(db: PostgresDatabase) -> None:
    history = PostgresHistory(db)
    big = [2**63 - 1, -(2**63), 2**53 + 1, 1682921346513461498]
    await write(history, [(T + i * S, {"x": v}) for i, v in enumerate(big)])
    assert [v for _, v in await all_values(history)] == big
    latest = await history.latest(TWIN, STREAM, None)
    assert latest["x"]["value"] == big[-1]
    got = await history.aggregate(TWIN, STREAM, None, T, T + 10 * S, 10 * S, ["sum", "min", "max"])
    assert got.rows[0]["values"]["x"] == {"sum": sum(big), "min": min(big), "max": max(big)}


async def test_partitions_are_made_for_any_time_and_dropped_whole(db: PostgresDatabase) -> None:
    history = PostgresHistory(db)
    times = [MIN_TIME, -1, 0, T, MAX_TIME]
    await write(history, [(t, {"x": i}) for i, t in enumerate(times)])
    assert await all_values(history) == [(t, i) for i, t in enumerate(times)]
    async with db.connection() as conn:
        made = await partitions.existing(conn)
    assert set(made) == {partitions.key_of(t) for t in times}
    # everything before T's partition goes as whole partitions, and T's own samples before
    # the cutoff row by row
    assert await history.delete_before(T + 1) == 4
    async with db.connection() as conn:
        assert set(await partitions.existing(conn)) == {
            partitions.key_of(T),
            partitions.key_of(MAX_TIME),
        }
    assert await all_values(history) == [(MAX_TIME, 4)]
    await write(history, [(0, {"x": 9})])  # a dropped range is made again
    assert await all_values(history) == [(0, 9), (MAX_TIME, 4)]
    [stream] = await history.streams(TWIN)
    assert (stream["values"], stream["first"], stream["last"]) == (2, 0, MAX_TIME)


async def test_a_batch_past_the_signal_limit_stores_nothing(db: PostgresDatabase) -> None:
    history = PostgresHistory(db, max_signals_per_stream=3)
    await write(history, [(T, {"a": 1, "b": 2})])
    with pytest.raises(TooManySignalsError, match="4 signals"):
        await write(history, [(T + S, {"c": 3, "d": 4})])
    assert [s["name"] for s in (await history.streams(TWIN))[0]["signals"]] == ["a", "b"]


async def test_a_read_over_its_time_is_stopped_by_the_server(db: PostgresDatabase) -> None:
    budget = ReadLimits(timeout_s=0.05).query()
    with pytest.raises(QueryTimeoutError, match=r"TWINLINK_HISTORY_QUERY_TIMEOUT_S \(0.05 s\)"):
        async with reading(db, budget) as conn:
            await conn.execute("SELECT pg_sleep(30)")  # stopped by statement_timeout
    history = PostgresHistory(db, limits=ReadLimits(timeout_s=0))
    await write(history, [(T, {"x": 1})])  # writes have no read budget
    with pytest.raises(QueryTimeoutError):
        await history.streams(TWIN)


async def test_an_answer_over_its_values_is_refused(db: PostgresDatabase) -> None:
    history = PostgresHistory(db, limits=ReadLimits(max_values=10))
    await write(history, [(T + i * S, {"x": i}) for i in range(20)])
    with pytest.raises(QueryTooLargeError, match="20 values; at most 10"):
        await history.aggregate(TWIN, STREAM, None, T, T + 20 * S, S, ["min"])
    with pytest.raises(QueryTooLargeError):
        await history.downsample(TWIN, STREAM, None, T, T + 20 * S, 15, "minmax")
    got = await history.aggregate(TWIN, STREAM, None, T, T + 20 * S, 10 * S, ["min", "max"])
    assert [row["values"]["x"] for row in got.rows] == [
        {"min": 0, "max": 9},
        {"min": 10, "max": 19},
    ]


async def until_gone(admin: asyncpg.Connection, pid: int) -> None:
    """Wait until the server's backend `pid` has ended (polled, with a deadline)."""
    async with asyncio.timeout(30):
        while await admin.fetchval("SELECT count(*) FROM pg_stat_activity WHERE pid = $1", pid):
            await asyncio.sleep(0.01)


async def test_a_connection_the_server_cuts_is_a_storage_error_and_the_next_works(
    db: PostgresDatabase, postgres_cluster: PostgresCluster
) -> None:
    history = PostgresHistory(db)
    admin = await asyncpg.connect(postgres_cluster.dsn())
    try:
        with pytest.raises(StorageError, match="cannot be reached or failed"):
            async with db.connection() as conn:
                pid = conn.get_server_pid()
                await admin.execute("SELECT pg_terminate_backend($1)", pid)
                await until_gone(admin, pid)
                await conn.fetchval("SELECT 1")
    finally:
        await admin.close()
    await write(history, [(T, {"x": 1})])  # the pool opens a new connection
    assert await all_values(history) == [(T, 1)]


async def test_a_twin_deleted_by_another_node_gets_new_series(postgres_dsn: str) -> None:
    nodes = [PostgresDatabase(postgres_dsn) for _ in range(2)]
    for node in nodes:
        await node.open()
    try:
        a, b = PostgresHistory(nodes[0]), PostgresHistory(nodes[1])
        await write(a, [(T, {"x": 1})])  # a caches the series' ids
        assert await b.delete_twin(TWIN) == 1
        await write(a, [(T + S, {"x": 2})])
        assert await all_values(b) == [(T + S, 2)]
        [stream] = await b.streams(TWIN)
        assert (stream["values"], stream["first"]) == (1, T + S)
    finally:
        for node in nodes:
            await node.close()


async def test_a_stream_retention_emptied_reads_empty_as_in_sqlite(db: PostgresDatabase) -> None:
    history = PostgresHistory(db)
    await write(history, [(T, {"x": 1})])
    assert await history.delete_before(T + S) == 1
    assert await history.samples(TWIN, STREAM, ["x"], MIN_TIME, MAX_TIME, 10) == SamplePage(
        [], None
    )
    assert await history.latest(TWIN, STREAM, None) == {}
    assert await history.extent(TWIN, STREAM, None) is None
    assert await history.streams(TWIN) == []


@pytest.mark.parametrize("fmt", ["csv", "jsonl", "json"])
async def test_an_export_of_many_pages_is_the_sqlite_backend_s_byte_for_byte(
    db: PostgresDatabase, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str
) -> None:
    monkeypatch.setattr(export, "PAGE_ROWS", 7)  # pages end inside runs of equal times
    rows: list[tuple[int, dict[str, Value]]]
    rows = [(T + (i // 3) * S, {"x": i, "y": f"v,{i}", "z": i / 4}) for i in range(60)]
    rows += [(T + 5 * S, {"x": -1}), (T + 5 * S, {"x": -2, "z": True})]  # late, equal times
    sqlite = SqliteHistory(tmp_path / "data", "normal")
    await sqlite.open()
    try:
        texts = []
        for store in (PostgresHistory(db), sqlite):
            await write(store, rows[:60])
            await write(store, rows[60:])
            names, pieces = await store.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, fmt, "iso")
            texts.append((names, b"".join([p async for p in pieces])))
    finally:
        await sqlite.close()
    assert texts[0] == texts[1]
    assert texts[0][1].count(b"\n") >= 60


def _column(i: int) -> dict[str, Value]:
    """A signal of ints (some past 2^53), one of floats with ties, one of ints and floats."""
    big = 2**62 + (i * 7919) % 1000
    return {"big": big, "wave": float((i * 37) % 11), "mix": i if i % 3 else i + 0.5}


async def both_backends(db: PostgresDatabase, folder: Path) -> AsyncIterator[HistoryStore]:
    """The PostgreSQL store and the SQLite one, each with the same 500 samples in batches of
    10 with out-of-order times."""
    sqlite = SqliteHistory(folder / "data", "normal")
    await sqlite.open()
    try:
        for store in (PostgresHistory(db), sqlite):
            for b in range(50):
                times = [T + ((b * 10 + k) * 7_919 % 500) * S // 10 for k in range(10)]
                await write(store, [(t, _column(b * 10 + k)) for k, t in enumerate(times)])
            yield store
    finally:
        await sqlite.close()


async def test_aggregates_are_the_sqlite_backend_s(db: PostgresDatabase, tmp_path: Path) -> None:
    fns = ["avg", "min", "max", "count", "first", "last", "sum"]
    answers = [
        await store.aggregate(TWIN, STREAM, None, T - 3 * S, T + 60 * S, 7 * S, fns)
        async for store in both_backends(db, tmp_path)
    ]
    assert answers[0] == answers[1]
    assert isinstance(answers[0].rows[0]["values"]["big"]["sum"], int)


@pytest.mark.parametrize("method", ["minmax", "lttb"])
async def test_downsamples_are_the_sqlite_backend_s(
    db: PostgresDatabase, tmp_path: Path, method: str
) -> None:
    answers = [
        await store.downsample(TWIN, STREAM, None, T, T + 50 * S, 24, method)
        async for store in both_backends(db, tmp_path)
    ]
    assert answers[0].keys() == answers[1].keys() == {"big", "mix", "wave"}
    for name, got in answers[0].items():
        want = answers[1][name]
        assert got.times.tolist() == want.times.tolist(), name
        assert got.values.tolist() == want.values.tolist(), name
        assert got.values.dtype == want.values.dtype, name
