"""The search API's tests (tests/integration/test_search.py: ranking, prefixes, facets, the
keyword filter, privacy, paging, query syntax) on a `twinlink up` server whose store is
PostgreSQL (TWINLINK_STORE_URL), a fresh database of the session's cluster (_postgres.py)."""

from __future__ import annotations

import asyncio
import secrets
from collections.abc import Iterator

import asyncpg
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration import test_search
from tests.integration._postgres import PostgresCluster, rerun_on_postgres
from tests.integration._postgres import postgres_cluster as postgres_cluster

pytestmark = pytest.mark.integration


async def _admin(cluster: PostgresCluster, sql: str) -> None:
    conn = await asyncpg.connect(cluster.dsn())
    try:
        await conn.execute(sql)
    finally:
        await conn.close()


@pytest.fixture(scope="module")
def database(postgres_cluster: PostgresCluster) -> Iterator[str]:
    """A database of the cluster for the module's server (dropped after); its DSN."""
    name = f"t_{secrets.token_hex(6)}"
    asyncio.run(_admin(postgres_cluster, f'CREATE DATABASE "{name}"'))
    try:
        yield postgres_cluster.dsn(name)
    finally:
        asyncio.run(_admin(postgres_cluster, f'DROP DATABASE "{name}" WITH (FORCE)'))


@pytest.fixture(scope="module")
def server(database: str, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """test_search's server, its store in PostgreSQL."""
    srv = start_server(tmp_path_factory.mktemp("data"), {"TWINLINK_STORE_URL": database})
    try:
        yield srv
    finally:
        stop_server(srv)


def test_the_twins_searched_are_in_postgresql(
    server: Server, examples: None, database: str
) -> None:
    async def count() -> int:
        conn = await asyncpg.connect(database)
        try:
            return int(await conn.fetchval("SELECT count(*) FROM search_parts"))
        finally:
            await conn.close()

    assert asyncio.run(count()) > 0
    assert not list(server.data_dir.glob("*.sqlite3"))  # and not in a SQLite file


rerun_on_postgres(test_search, globals())
