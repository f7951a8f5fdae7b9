"""tests/unit/test_ingest_published.py on PostgreSQL, and what this backend adds: a batch
committed whose publish failed (Kafka away) is published by its resend, once; the mark that
it was published is written after the ack, lazily, and a mark not written only makes a
resend publish again (docs/decisions/0013)."""

from __future__ import annotations

import asyncio

import asyncpg
import pytest

from tests.integration._postgres import history as history
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.unit import test_ingest_published
from tests.unit.test_ingest_published import DEVICE, FlakyBus, body, seqs
from twinlink.domain.errors import UnavailableError
from twinlink.ingest.service import IngestService
from twinlink.store.postgres.db import PostgresDatabase, migrate
from twinlink.store.postgres.history import PostgresHistory

rerun_on_postgres(test_ingest_published, globals())

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]


async def published_flags(dsn: str) -> dict[int, bool]:
    conn = await asyncpg.connect(dsn)
    try:
        rows = await conn.fetch("SELECT seq, published FROM ingested WHERE device_id = $1", 3)
    finally:
        await conn.close()
    return {seq: flag for seq, flag in rows}


async def marked_published(dsn: str, seq: int) -> None:
    """Wait for the node's lazy mark of `seq` (written after the ack, in the background)."""
    async with asyncio.timeout(20):
        while not (await published_flags(dsn)).get(seq):
            await asyncio.sleep(0.02)  # polling the database's state, with a deadline


async def test_a_batch_stored_but_not_published_is_published_by_its_resend_once(
    ingest: IngestService, bus: FlakyBus, postgres_dsn: str
) -> None:
    bus.down = True  # Kafka away after the commit: the device is answered 503
    with pytest.raises(UnavailableError):
        await ingest.ingest(DEVICE, body(1))
    assert await published_flags(postgres_dsn) == {1: False}  # stored, not on the bus
    bus.down = False
    resent = await ingest.ingest(DEVICE, body(1))
    assert (resent.accepted, resent.duplicate) == (0, True)  # stored once, by the first try
    assert seqs(bus) == [1]  # ... and on the bus now
    await marked_published(postgres_dsn, 1)
    await ingest.ingest(DEVICE, body(1))  # a third time (its ack lost): not published again
    assert seqs(bus) == [1]


async def test_a_node_that_stopped_between_commit_and_publish_leaves_it_to_the_resend(
    postgres_dsn: str,
) -> None:
    # The first node commits and is gone before its publish (no mark); a second node,
    # with a fresh cache of pending marks, takes the resend.
    bus = FlakyBus()
    for attempt in range(2):
        db = PostgresDatabase(postgres_dsn)
        store = PostgresHistory(db)
        await db.open()
        try:
            ingest = IngestService(test_ingest_published.Registry(), store, bus)  # type: ignore[arg-type]
            bus.down = attempt == 0
            if attempt == 0:
                with pytest.raises(UnavailableError):
                    await ingest.ingest(DEVICE, body(5))
            else:
                assert (await ingest.ingest(DEVICE, body(5))).duplicate
        finally:
            await store.close()
            await db.close()
    assert seqs(bus) == [5]
    assert await published_flags(postgres_dsn) == {5: True}  # close() wrote the mark


async def test_batches_stored_before_the_upgrade_count_as_published(postgres_dsn: str) -> None:
    # a database of the version before `published` (0002): its batches went on the bus
    # when they were stored, so a resend of one must not publish it again
    conn = await asyncpg.connect(postgres_dsn)
    try:
        assert await migrate(conn, target=2) == [1, 2]
        await conn.execute("INSERT INTO ingested (device_id, seq, at_ns) VALUES (3, 9, 1)")
        await migrate(conn)
    finally:
        await conn.close()
    assert await published_flags(postgres_dsn) == {9: True}
