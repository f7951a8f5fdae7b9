"""Group commit of PostgreSQL history (store/postgres/history/group.py): many concurrent
appends go in a few transactions and store exactly what writing them one by one stores
(rows, /streams summaries, latest values, each append's answer); a refused batch, a stale
series cache and a partition dropped by another node fail no other batch; two nodes whose
groups share batches store each once, without a deadlock."""

from __future__ import annotations

import asyncio
import secrets
from collections.abc import AsyncIterator
from typing import Any

import asyncpg
import pytest

from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.unit._history import S, T
from twinlink.domain.errors import TooManySignalsError
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history import PostgresHistory, partitions

pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]

MAX_SIGNALS = 8
TWINS = range(1, 6)
STREAMS = ("a", "b")


@pytest.fixture
async def db(postgres_dsn: str) -> AsyncIterator[PostgresDatabase]:
    async with _opened(postgres_dsn) as database:
        yield database


@pytest.fixture
async def reference_db(postgres_cluster: PostgresCluster) -> AsyncIterator[PostgresDatabase]:
    """A second database, written one batch at a time: what the group must equal."""
    name = f"t_{secrets.token_hex(6)}"
    admin = await asyncpg.connect(postgres_cluster.dsn())
    try:
        await admin.execute(f'CREATE DATABASE "{name}"')
        try:
            async with _opened(postgres_cluster.dsn(name)) as database:
                yield database
        finally:
            await admin.execute(f'DROP DATABASE "{name}" WITH (FORCE)')
    finally:
        await admin.close()


class _opened:
    def __init__(self, dsn: str) -> None:
        self.db = PostgresDatabase(dsn)

    async def __aenter__(self) -> PostgresDatabase:
        await self.db.open()
        return self.db

    async def __aexit__(self, *exc: object) -> None:
        await self.db.close()


def batch(twin_id: int, stream: str, seq: int | None, rows: list[dict[str, Value]]) -> SampleBatch:
    # times repeat across batches and within one: the latest value and the order of samples
    # at equal times then depend on the order of arrival
    times = [T + (seq or 0) % 4 * S + i // 2 * S for i in range(len(rows))]
    return SampleBatch(twin_id, f"twin{twin_id}", stream, times, rows, T, seq=seq)


def device_batch(device: int, seq: int) -> SampleBatch:
    """Device `device`'s batch `seq`: two devices share each stream; the signal `m` is of
    another kind from batch to batch (ints, floats, text, bools), `x` mixes ints and
    floats in one batch, `s` is text."""
    twin_id, stream = TWINS[device % 5], STREAMS[device // 5 % 2]
    kind = (device + seq) % 4
    rows: list[dict[str, Value]] = []
    for i in range(3 + seq % 3):
        m: Value = [i * seq, i + 0.5, f"m{i}", i % 2 == 0][kind]
        rows.append({"x": i if i % 2 else i + 0.25, "m": m, "s": f"{device}/{seq}/{i}"})
        if (device + i) % 3 == 0:
            rows[-1][f"d{device % 4}"] = device * 1000 + seq
    return batch(twin_id, stream, seq, rows)


def too_many(twin_id: int, stream: str) -> SampleBatch:
    """A batch that would give its stream more than MAX_SIGNALS signals."""
    return batch(twin_id, stream, None, [{f"new{i}": i for i in range(MAX_SIGNALS)}])


def workload() -> list[tuple[SampleBatch, int | None]]:
    """200 appends of 20 devices: 10 of them resent (the same (device, seq) twice in the
    group), 10 refused, some without a (device, seq) (a processor's output)."""
    sent: list[tuple[SampleBatch, int | None]] = []
    for seq in range(9):
        for device in range(20):
            sent.append((device_batch(device, seq), device + 100))
            if seq == 4 and device < 10:  # sent twice (the device did not get the ack)
                sent.append((device_batch(device, seq), device + 100))
        if seq % 2:
            sent.append((too_many(TWINS[seq % 5], STREAMS[seq % 2]), None))
    while len(sent) < 200:
        n = len(sent)
        sent.append((batch(TWINS[n % 5], "c", None, [{"x": n, "y": n % 3 == 0}]), None))
    return sent


async def answer(history: PostgresHistory, item: tuple[SampleBatch, int | None]) -> object:
    try:
        return await history.append(*item)
    except TooManySignalsError:
        return "refused"


async def stored(db: PostgresDatabase) -> dict[str, list[tuple[Any, ...]]]:
    """Everything history keeps, batch ids as their rank (the same in both databases)."""
    async with db.connection() as conn:
        samples = await conn.fetch(
            "SELECT st.twin_id, st.name, se.signal, sa.t, dense_rank() OVER (ORDER BY sa.batch), "
            "sa.pos, sa.kind, sa.vi, sa.vf, sa.vb, sa.vj FROM samples sa "
            "JOIN series se ON se.id = sa.series_id JOIN streams st ON st.id = sa.stream_id "
            "ORDER BY 1, 2, 3, 4, 5, 6"
        )
        series = await conn.fetch(
            "SELECT st.twin_id, st.name, se.signal, se.n, se.first_t, se.last_t, se.kinds "
            "FROM series se JOIN streams st ON st.id = se.stream_id ORDER BY 1, 2, 3"
        )
        latest = await conn.fetch(
            "SELECT st.twin_id, st.name, se.signal, l.t, l.value FROM latest l "
            "JOIN series se ON se.id = l.series_id JOIN streams st ON st.id = se.stream_id "
            "ORDER BY 1, 2, 3"
        )
        ingested = await conn.fetch("SELECT device_id, seq FROM ingested ORDER BY 1, 2")
    return {
        "samples": [tuple(r) for r in samples],
        "series": [tuple(r) for r in series],
        "latest": [tuple(r) for r in latest],
        "ingested": [tuple(r) for r in ingested],
    }


async def shown(history: PostgresHistory) -> list[Any]:
    """What the API shows of each twin: /streams and each stream's latest values."""
    found: list[Any] = []
    for twin_id in TWINS:
        streams = await history.streams(twin_id)
        found.append(streams)
        for stream in streams:
            found.append(await history.latest(twin_id, stream["name"], None))
    return found


async def test_concurrent_appends_store_what_one_by_one_writing_stores(
    db: PostgresDatabase, reference_db: PostgresDatabase
) -> None:
    grouped = PostgresHistory(db, max_signals_per_stream=MAX_SIGNALS)
    reference = PostgresHistory(reference_db, max_signals_per_stream=MAX_SIGNALS)
    # half the streams are known (cached) before, the others are made by the group
    warm = [(device_batch(d, 100), d + 100) for d in range(0, 20, 2)]
    for item in warm:
        assert await grouped.append(*item)
        assert await reference.writer.append(*item)  # today's path: one batch, one transaction
    before = grouped.groups.groups
    sent = workload()
    answers = await asyncio.gather(*(answer(grouped, item) for item in sent))
    expected = [await _answer_one(reference, item) for item in sent]
    assert answers == expected
    assert answers.count("refused") == 4
    assert answers.count(False) == 10  # the resends
    assert answers.count(True) == 186
    assert grouped.groups.fallbacks == 0
    assert 1 <= grouped.groups.groups - before <= 10  # 200 batches, a handful of transactions
    assert await stored(db) == await stored(reference_db)
    assert await shown(grouped) == await shown(reference)
    # a refused batch left the others of its stream (and of its group) stored
    streams = {s["name"]: s for s in await grouped.streams(TWINS[1])}
    signals = {signal["name"] for signal in streams["b"]["signals"]}
    assert {"x", "m", "s"} <= signals
    assert not any(name.startswith("new") for name in signals)


async def _answer_one(history: PostgresHistory, item: tuple[SampleBatch, int | None]) -> object:
    try:
        return await history.writer.append(*item)
    except TooManySignalsError:
        return "refused"


async def test_a_stale_series_cache_fails_no_batch(postgres_dsn: str) -> None:
    async with _opened(postgres_dsn) as one, _opened(postgres_dsn) as other:
        node, node2 = PostgresHistory(one), PostgresHistory(other)
        assert await node.append(batch(1, "a", 1, [{"x": 1}]), 100)
        await node2.delete_twin(1)  # the first node's cached series ids of twin 1 are gone
        sent = [(batch(1 + n % 2, "a", n + 10, [{"x": n}, {"x": n + 1}]), 100) for n in range(8)]
        assert await asyncio.gather(*(node.append(*item) for item in sent)) == [True] * 8
        assert node.groups.fallbacks == 1  # the group was written again batch by batch
        for twin_id in (1, 2):
            page = await node.samples(twin_id, "a", None, MIN_TIME, MAX_TIME, 100)
            assert len(page.rows) == 8  # 4 batches of 2 rows each
            [summary] = await node.streams(twin_id)
            assert summary["values"] == 8


async def test_a_partition_dropped_by_another_node_fails_no_batch(postgres_dsn: str) -> None:
    async with _opened(postgres_dsn) as one, _opened(postgres_dsn) as other:
        node, node2 = PostgresHistory(one), PostgresHistory(other)
        early = SampleBatch(1, "twin1", "a", [5], [{"x": 0}], T, seq=1)
        assert await node.append(early, 100)
        assert await node2.delete_before(1 << partitions.WIDTH_BITS) == 1  # dropped whole
        sent = [
            SampleBatch(1 + n % 2, f"twin{1 + n % 2}", "a", [10 + n], [{"x": n}], T, seq=n + 2)
            for n in range(6)
        ]
        answers = await asyncio.gather(*(node.append(b, 100 + b.twin_id) for b in sent))
        assert answers == [True] * 6
        assert node.groups.fallbacks == 1
        page = await node.samples(1, "a", None, MIN_TIME, MAX_TIME, 100)
        assert [row["values"]["x"] for row in page.rows] == [0, 2, 4]


async def test_two_nodes_whose_groups_share_batches_store_each_once(postgres_dsn: str) -> None:
    async with _opened(postgres_dsn) as one, _opened(postgres_dsn) as other:
        nodes = [PostgresHistory(one), PostgresHistory(other)]
        for round_ in range(3):  # the second and third rounds find the series cached
            seqs = range(5 * round_, 5 * round_ + 5)
            sent = [(device_batch(d, seq), d + 100) for seq in seqs for d in range(20)]
            # the nodes take the same batches in opposite orders
            first, second = await asyncio.gather(
                asyncio.gather(*(nodes[0].append(*item) for item in sent)),
                asyncio.gather(*(nodes[1].append(*item) for item in sent[::-1])),
            )
            # each stored by one node, found stored by the other
            assert all(a != b for a, b in zip(first, second[::-1], strict=True))
        assert all(node.groups.fallbacks == 0 for node in nodes)  # no deadlock, no retry
        async with one.connection() as conn:
            assert await conn.fetchval("SELECT count(*) FROM ingested") == 300
            per_batch = await conn.fetchval(
                "SELECT count(*) FROM (SELECT DISTINCT batch, stream_id FROM samples) b"
            )
        assert per_batch == 300
