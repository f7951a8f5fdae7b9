"""The PostgreSQL backend's schema migrations (store/postgres/db.py), on a real server: a
database of an older version is upgraded with its data kept, nodes that start together
migrate once, and a server that cannot be reached is a StorageError saying so."""

from __future__ import annotations

import asyncio

import asyncpg
import pytest

from tests.conftest import free_port
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from twinlink.domain.commands import CommandRecord
from twinlink.domain.errors import StorageError
from twinlink.store.postgres.commands import PostgresCommands
from twinlink.store.postgres.db import PostgresDatabase, migrate, migrations, schema_version

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]

VERSIONS = [version for version, _, _ in migrations()]
LATEST = VERSIONS[-1]


def test_migrations_are_numbered_in_order_each_number_once() -> None:
    # numbers may leave gaps (a range per area: history 1-9, metadata from 10), never repeat
    assert VERSIONS[:2] == [1, 2] and sorted(set(VERSIONS)) == VERSIONS


async def test_an_old_database_is_upgraded_and_keeps_its_commands(postgres_dsn: str) -> None:
    conn = await asyncpg.connect(postgres_dsn)
    try:
        assert await migrate(conn, target=1) == [1]
        await conn.execute(
            "INSERT INTO commands (id, twin_id, device_id, device, name, args, state, queued, "
            "created_ns, expires_ns) VALUES ('c1', 7, 3, 'dev', 'pause', '{\"a\": 1}', "
            "'pending', true, 10, 20)"
        )
    finally:
        await conn.close()

    db = PostgresDatabase(postgres_dsn)
    await db.open()  # migrates the rest
    try:
        async with db.connection() as pooled:
            assert await schema_version(pooled) == LATEST
            assert await pooled.fetchval("SELECT to_regclass('samples') IS NOT NULL")
        stored = await PostgresCommands(db).get_command("c1")
    finally:
        await db.close()
    assert stored == CommandRecord(
        id="c1", twin_id=7, device_id=3, device="dev", name="pause", args={"a": 1},
        state="pending", queued=True, sent_by=None, created_ns=10, expires_ns=20,
    )  # fmt: skip


async def test_a_lower_number_shipped_after_a_higher_one_is_applied(postgres_dsn: str) -> None:
    # numbers are given out in ranges, so a database may have 10 and not yet 2
    later = next(v for v in VERSIONS if v >= 10)
    sql = {version: text for version, _, text in migrations()}
    conn = await asyncpg.connect(postgres_dsn)
    try:
        assert await migrate(conn, target=1) == [1]
        async with conn.transaction():
            await conn.execute(sql[later])
            await conn.execute("INSERT INTO twinlink_schema (version) VALUES ($1)", later)
        applied = await migrate(conn)
        stored = {r[0] for r in await conn.fetch("SELECT version FROM twinlink_schema")}
    finally:
        await conn.close()
    assert applied == [v for v in VERSIONS if v not in (1, later)]
    assert stored == set(VERSIONS)


async def test_nodes_starting_together_migrate_once(postgres_dsn: str) -> None:
    conns = [await asyncpg.connect(postgres_dsn) for _ in range(3)]
    try:
        applied = await asyncio.gather(*(migrate(c) for c in conns))
        assert sorted(v for one in applied for v in one) == VERSIONS
        assert await migrate(conns[0]) == []  # up to date: nothing to do
        versions = await conns[0].fetch("SELECT version FROM twinlink_schema ORDER BY version")
        assert [r[0] for r in versions] == VERSIONS
    finally:
        for c in conns:
            await c.close()


async def test_an_unreachable_server_is_a_storage_error_that_says_so() -> None:
    db = PostgresDatabase(f"postgresql://twinlink:secret-pw@127.0.0.1:{free_port()}/none")
    with pytest.raises(StorageError, match="Cannot connect to PostgreSQL") as caught:
        await db.open()
    assert "secret-pw" not in str(caught.value)
