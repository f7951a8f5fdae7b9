"""A real PostgreSQL server for the tests: one cluster for the whole run, a database per test.

`postgres_cluster` (session scope) runs Debian's `postgresql` binaries (`make test` installs
them) on a fresh cluster in a temporary folder, on a free loopback port; `postgres_dsn` gives
each test a database of its own, created for it and dropped after. A module opts in by
importing the fixtures (`from tests.integration._postgres import postgres_dsn as postgres_dsn`,
and `postgres_cluster` beside it).

Starting the server is twinlink.devcluster.postgres's (the local cluster's too); initdb and
postgres refuse to run as root, so run as root (as CI is) the cluster belongs to the
`postgres` user the package creates and the server runs as that user. The server is this
process's child from the first test that asks for it to the end of the run, so the hygiene
check (tests/_hygiene.py) counts it, and the backends it forks for connections, as there
before every test.
"""

from __future__ import annotations

import inspect
import secrets
import shutil
import subprocess
import tempfile
import time
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import asyncpg
import pytest

from tests.conftest import free_port
from tests.unit._storage import Stores, opened
from twinlink.devcluster import postgres as devcluster_postgres
from twinlink.store.history import HistoryStore
from twinlink.store.postgres.commands import PostgresCommands
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history import PostgresHistory
from twinlink.store.postgres.metadata import PostgresMetadataStore
from twinlink.store.postgres.properties import PostgresProperties

SQLITE_ONLY = frozenset({"sqlite_history"})  # fixtures of tests of SQLite's own workings
START_S = devcluster_postgres.START_S
SUPERUSER = devcluster_postgres.SUPERUSER


@dataclass(frozen=True)
class PostgresCluster:
    host: str
    port: int
    folder: Path

    def dsn(self, database: str = "postgres") -> str:
        # trust on loopback (initdb --auth=trust): a throwaway cluster with no secrets in it
        return f"postgresql://{SUPERUSER}@{self.host}:{self.port}/{database}"


def postgres_bin() -> Path:
    """The folder of the newest installed PostgreSQL's programs (twinlink.devcluster.postgres);
    the test fails saying what to install when there is none."""
    try:
        return devcluster_postgres.postgres_bin()
    except devcluster_postgres.PostgresError as err:
        pytest.fail(str(err), pytrace=False)


_run_as = devcluster_postgres.run_as
_ready = devcluster_postgres.ready


def _start(
    bin_dir: Path, folder: Path, port: int | None = None
) -> tuple[subprocess.Popen[bytes], int]:
    """initdb in `folder` (unless done: starting again on the same folder and port is a
    restart that keeps the data) and start a throwaway server (fsync off, trust on loopback)
    on `port` or a free one, without waiting for it (`_ready`)."""
    devcluster_postgres.initdb(bin_dir, folder, throwaway=True)
    port = port or free_port()
    # the fixture runs in pytest's main thread, whose exit is what the kernel watches
    return devcluster_postgres.launch(bin_dir, folder, port, throwaway=True), port


_stop = devcluster_postgres.stop_postgres


@pytest.fixture(scope="session")
def postgres_cluster() -> Iterator[PostgresCluster]:
    bin_dir = postgres_bin()
    folder = Path(tempfile.mkdtemp(prefix="twinlink-pg-"))
    try:
        server, port = _start(bin_dir, folder)
        try:
            deadline = time.monotonic() + START_S
            while not _ready(bin_dir, port):
                if server.poll() is not None or time.monotonic() > deadline:
                    log = (folder / "postgres.log").read_text(errors="replace")
                    pytest.fail(f"PostgreSQL did not start on port {port}:\n{log[-3000:]}")
                time.sleep(0.05)  # polling the server's real state, with a deadline
            yield PostgresCluster("127.0.0.1", port, folder)
        finally:
            _stop(server)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture
async def postgres_dsn(postgres_cluster: PostgresCluster) -> AsyncIterator[str]:
    """A fresh, empty database of the cluster, dropped after the test."""
    name = f"t_{secrets.token_hex(6)}"
    admin = await asyncpg.connect(postgres_cluster.dsn())
    try:
        await admin.execute(f'CREATE DATABASE "{name}"')
        try:
            yield postgres_cluster.dsn(name)
        finally:
            await admin.execute(f'DROP DATABASE "{name}" WITH (FORCE)')
    finally:
        await admin.close()


class PostgresBackend:
    """The PostgreSQL backend for the service-level tests (`tests.unit._storage.Backend`):
    metadata, history, commands and properties in the database at `dsn`."""

    def __init__(self, dsn: str) -> None:
        self.dsn = dsn

    @asynccontextmanager
    async def stores(self, folder: Path) -> AsyncIterator[Stores]:
        db = PostgresDatabase(self.dsn)
        stores = Stores(
            PostgresMetadataStore(db), PostgresHistory(db), PostgresCommands(db),
            PostgresProperties(db),
        )  # fmt: skip
        async with opened(db, stores.metadata, stores.history, stores.commands, stores.properties):
            yield stores

    @asynccontextmanager
    async def history(self, folder: Path) -> AsyncIterator[HistoryStore]:
        db = PostgresDatabase(self.dsn)
        history = PostgresHistory(db)
        async with opened(db, history):
            yield history


@pytest.fixture
async def stores(postgres_dsn: str, tmp_path: Path) -> AsyncIterator[Stores]:
    """`tests.unit._storage.stores` on PostgreSQL."""
    async with PostgresBackend(postgres_dsn).stores(tmp_path) as opened_stores:
        yield opened_stores


@pytest.fixture
async def history(postgres_dsn: str, tmp_path: Path) -> AsyncIterator[HistoryStore]:
    """`tests.unit._history.history` on PostgreSQL."""
    async with PostgresBackend(postgres_dsn).history(tmp_path) as store:
        yield store


def rerun_on_postgres(module: ModuleType, namespace: dict[str, Any]) -> None:
    """Copy the tests and fixtures of a service-level test module (one whose tests take
    `stores` or `history`, tests/unit/_storage.py) into the module whose `namespace` this is,
    but for the names it has already: it imports `stores`, `history` and `postgres_*` from
    here first, so the copied fixtures and tests, which ask for them by name, get PostgreSQL.
    The unit run stays server-free; the same test functions run again here, against a real
    server, as integration tests. Tests that take a fixture of `sqlite_only` (a backend's own
    workings) are left out."""
    for name, value in vars(module).items():
        if name.startswith("__") or name in namespace:
            continue
        if name.startswith("test_") and SQLITE_ONLY & set(inspect.signature(value).parameters):
            continue
        namespace[name] = value
