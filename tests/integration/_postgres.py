"""A real PostgreSQL server for the tests: one cluster for the whole run, a database per test.

`postgres_cluster` (session scope) runs Debian's `postgresql` binaries (`make test` installs
them) on a fresh cluster in a temporary folder, on a free loopback port; `postgres_dsn` gives
each test a database of its own, created for it and dropped after. A module opts in by
importing the fixtures (`from tests.integration._postgres import postgres_dsn as postgres_dsn`,
and `postgres_cluster` beside it).

initdb and postgres refuse to run as root: run as root (as CI is), the cluster belongs to the
`postgres` user the package creates and the server runs as that user; run as anyone else, as
that user. The server is this process's child from the first test that asks for it to the
end of the run, so the hygiene check (tests/_hygiene.py) counts it, and the backends it
forks for connections, as there before every test.
"""

from __future__ import annotations

import ctypes
import inspect
import os
import pwd
import secrets
import shutil
import signal
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
from twinlink.store.history import HistoryStore
from twinlink.store.postgres.commands import PostgresCommands
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history import PostgresHistory
from twinlink.store.postgres.metadata import PostgresMetadataStore
from twinlink.store.postgres.properties import PostgresProperties

SQLITE_ONLY = frozenset({"sqlite_history"})  # fixtures of tests of SQLite's own workings
START_S = 60.0  # a cold initdb and start on a busy 2-core machine take a few seconds
SUPERUSER = "postgres"
_PR_SET_PDEATHSIG = 1


@dataclass(frozen=True)
class PostgresCluster:
    host: str
    port: int
    folder: Path

    def dsn(self, database: str = "postgres") -> str:
        # trust on loopback (initdb --auth=trust): a throwaway cluster with no secrets in it
        return f"postgresql://{SUPERUSER}@{self.host}:{self.port}/{database}"


def postgres_bin() -> Path:
    """The folder of the newest installed PostgreSQL's programs (Debian keeps them out of
    PATH, in /usr/lib/postgresql/VERSION/bin)."""
    versions = sorted(
        Path("/usr/lib/postgresql").glob("*/bin/postgres"),
        key=lambda p: int(p.parent.parent.name) if p.parent.parent.name.isdigit() else 0,
    )
    if versions:
        return versions[-1].parent
    found = shutil.which("postgres")
    if found is None:
        pytest.fail(
            "PostgreSQL not found: install the Debian package postgresql (make test does: "
            "scripts/ensure-packages.sh)"
        )
    return Path(found).parent


def _run_as() -> dict[str, object]:
    """Popen's arguments that run a program as the cluster's owner: `postgres` when we are
    root, ourselves otherwise."""
    if os.geteuid() != 0:
        return {}
    owner = pwd.getpwnam(SUPERUSER)
    return {"user": owner.pw_uid, "group": owner.pw_gid, "extra_groups": []}


def _ready(bin_dir: Path, port: int) -> bool:
    done = subprocess.run(
        [bin_dir / "pg_isready", "-q", "-h", "127.0.0.1", "-p", str(port)], check=False
    )
    return done.returncode == 0


def _start(bin_dir: Path, folder: Path) -> tuple[subprocess.Popen[bytes], int]:
    data, sockets = folder / "data", folder / "sockets"
    sockets.mkdir()
    if os.geteuid() == 0:
        owner = pwd.getpwnam(SUPERUSER)
        for path in (folder, sockets):
            os.chown(path, owner.pw_uid, owner.pw_gid)
    subprocess.run(
        [bin_dir / "initdb", "-D", data, "-U", SUPERUSER, "--auth=trust", "-E", "UTF8",
         "--locale=C.UTF-8", "--no-sync"],
        check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, **_run_as(),  # type: ignore[call-overload]
    )  # fmt: skip
    port = free_port()
    log = (folder / "postgres.log").open("wb")
    # fsync and full-page writes off: a crash of the test machine loses a throwaway cluster
    server = subprocess.Popen(
        [bin_dir / "postgres", "-D", data, "-p", str(port), "-k", sockets,
         "-c", "listen_addresses=127.0.0.1", "-c", "fsync=off", "-c", "full_page_writes=off",
         "-c", "synchronous_commit=off", "-c", "max_connections=200"],
        stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
        # the fixture runs in pytest's main thread, whose exit is what the kernel watches
        preexec_fn=_die_with_parent, **_run_as(),  # type: ignore[call-overload]
    )  # fmt: skip
    log.close()
    return server, port


def _die_with_parent() -> None:
    """In the child before exec (after it became the cluster's owner, which would clear the
    setting): the kernel stops the server at once (SIGQUIT, "immediate shutdown") when pytest
    dies, even by SIGKILL, so an interrupted run leaves no server behind."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGQUIT)


def _stop(server: subprocess.Popen[bytes]) -> None:
    server.send_signal(signal.SIGINT)  # "fast" shutdown: ends the sessions, no waiting for them
    try:
        server.wait(30)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()


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
