"""A `twinlink up` server whose store is PostgreSQL (TWINLINK_STORE_URL), for re-running a
module of server tests on it: the module imports `server` and `database` from here (and
`postgres_cluster` from _postgres.py), then `rerun_on_postgres(that_module, globals())`.
Each module gets a fresh database of the session's cluster, dropped after."""

from __future__ import annotations

import asyncio
import secrets
from collections.abc import Iterator

import asyncpg
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._postgres import PostgresCluster


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
    """The module's server (as tests/conftest.py's), its store in PostgreSQL."""
    srv = start_server(tmp_path_factory.mktemp("data"), {"TWINLINK_STORE_URL": database})
    try:
        yield srv
    finally:
        stop_server(srv)


def count(dsn: str, sql: str) -> int:
    """One number read straight from the database, apart from the server."""

    async def read() -> int:
        conn = await asyncpg.connect(dsn)
        try:
            return int(await conn.fetchval(sql))
        finally:
            await conn.close()

    return asyncio.run(read())
