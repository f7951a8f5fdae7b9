"""Nodes of the scale-out setup for the tests: `twinlink up` processes on one PostgreSQL
database (a fresh one per module, in the session's cluster, tests/integration/_postgres.py)
and the session's Kafka broker (tests/integration/_kafka.py), sharing one secret key."""

from __future__ import annotations

import asyncio
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import asyncpg
from cryptography.fernet import Fernet

from tests.conftest import Server, start_server
from tests.integration._kafka import KafkaBroker
from tests.integration._postgres import PostgresCluster


@dataclass(frozen=True)
class Cluster:
    """What the nodes share: the environment that points them at it, and the database."""

    dsn: str
    env: dict[str, str]

    password: str  # in the store URL; the test cluster trusts loopback and never asks for it

    def start(self, data_dir: Path, *, token: str | None = None, **env: str) -> Server:
        """A node with a data dir of its own (only the vault's key would live there, and
        TWINLINK_SECRET_KEY keeps it out)."""
        return start_server(data_dir, {**self.env, **env}, token=token)

    def fetchval(self, sql: str, *args: object) -> object:
        """One value read straight from the database, apart from any node."""

        async def read() -> object:
            conn = await asyncpg.connect(self.dsn)
            try:
                return await conn.fetchval(sql, *args)
            finally:
                await conn.close()

        return asyncio.run(read())


@contextmanager
def cluster(postgres: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    """A fresh database (dropped at the end) and the session's broker. The nodes use the
    default topics: a node reads them from where they ended when it started, so what the
    nodes of a module run before published is not seen here."""
    name = f"t_{secrets.token_hex(6)}"
    asyncio.run(_admin(postgres, f'CREATE DATABASE "{name}"'))
    try:
        password = f"pw-{secrets.token_hex(8)}"
        url = postgres.dsn(name).replace("://postgres@", f"://postgres:{password}@", 1)
        assert password in url
        env = {
            "TWINLINK_STORE_URL": url,
            "TWINLINK_BUS_URL": f"kafka://{kafka.bootstrap}",
            "TWINLINK_SECRET_KEY": Fernet.generate_key().decode(),
        }
        yield Cluster(postgres.dsn(name), env, password)
    finally:
        asyncio.run(_admin(postgres, f'DROP DATABASE "{name}" WITH (FORCE)'))


async def _admin(postgres: PostgresCluster, sql: str) -> None:
    conn = await asyncpg.connect(postgres.dsn())
    try:
        await conn.execute(sql)
    finally:
        await conn.close()
