"""A `twinlink up` server whose store is PostgreSQL (TWINLINK_STORE_URL), for re-running a
module of server tests on it: the module imports `server` (or makes one with
`server_on_postgres` from its own server maker) and `database` from here, and
`postgres_cluster` from _postgres.py, then `rerun_on_postgres(that_module, globals())` and
`drop_tests_without_server(globals())`.
Each module gets a fresh database of the session's cluster, dropped after."""

from __future__ import annotations

import asyncio
import inspect
import secrets
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

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


def server_on_postgres(start: Callable[..., Server]) -> Any:
    """A module fixture `server` started by `start(data_dir, **env)` (a module's own server
    maker, with its settings), its store in the module's database."""

    @pytest.fixture(scope="module", name="server")
    def fixture(database: str, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
        srv = start(tmp_path_factory.mktemp("data"), TWINLINK_STORE_URL=database)
        try:
            yield srv
        finally:
            stop_server(srv)

    return fixture


def _plain(data_dir: Path, **env: str) -> Server:
    return start_server(data_dir, env)


# tests/conftest.py's server, its store in PostgreSQL
server = server_on_postgres(_plain)


def drop_tests_without_server(namespace: dict[str, Any]) -> None:
    """Leave out the tests copied into `namespace` that start servers of their own: those
    run on SQLite, and already ran there in their own module."""
    for name in [n for n, v in namespace.items() if n.startswith("test_") and callable(v)]:
        if "server" not in inspect.signature(namespace[name]).parameters:
            del namespace[name]


def count(dsn: str, sql: str) -> int:
    """One number read straight from the database, apart from the server."""

    async def read() -> int:
        conn = await asyncpg.connect(dsn)
        try:
            return int(await conn.fetchval(sql))
        finally:
            await conn.close()

    return asyncio.run(read())
