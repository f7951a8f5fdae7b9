"""A pool of asyncpg connections to one database, and its numbered schema migrations.

The stores of this backend share one `PostgresDatabase`; the composition root opens it
before them and closes it after. Opening applies the migrations this version ships
(migrations/NNNN_name.sql, in order, each in one transaction) under an advisory lock, so
nodes that start together against one database migrate it once. A failure of the server
or of the connection to it leaves the stores as StorageError (HTTP 503 with Retry-After),
a full disk as StorageFullError (507), a broken unique constraint or foreign key as
WriteConflictError, text with a NUL character as InvalidInputError: no asyncpg error leaves
the backend.
"""

from __future__ import annotations

import logging
import re
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from importlib import resources

import asyncpg
from asyncpg.pool import PoolConnectionProxy

from twinlink.domain.errors import (
    InvalidInputError,
    StorageError,
    StorageFullError,
    WriteConflictError,
)

log = logging.getLogger("twinlink.store")

# A connection of its own (a migration run by hand, a test) or one lent by the pool.
Connection = asyncpg.Connection | PoolConnectionProxy

_MIGRATION_NAME = re.compile(r"^(\d{4})_[a-z0-9_]+\.sql$")
# Any number that is ours alone: pg_advisory_xact_lock takes a 64-bit key per database.
_MIGRATION_LOCK = 0x7477_6C6E_6B00_0001
UNREACHABLE = (
    "The server's database (PostgreSQL) cannot be reached or failed the request: nothing of "
    "this was stored. Retry later."
)
FULL = (
    "The server's database (PostgreSQL) is out of disk space: nothing of this was stored. "
    "Retry once an administrator has freed disk space."
)

# SQLite stores text with a NUL character; PostgreSQL's text cannot hold one at all.
NUL = (
    "Text with a NUL character (U+0000) cannot be stored or looked up in this server's "
    "database (PostgreSQL): remove the character and send it again."
)


def migrations() -> list[tuple[int, str, str]]:
    """(version, file name, SQL) of every migration shipped in the package, in order."""
    folder = resources.files("twinlink.store.postgres").joinpath("migrations")
    found = []
    for entry in folder.iterdir():
        match = _MIGRATION_NAME.match(entry.name)
        if match:
            found.append((int(match.group(1)), entry.name, entry.read_text("utf-8")))
    return sorted(found)


async def schema_version(conn: Connection) -> int:
    """The version the database is at; 0 when it has no schema of ours yet."""
    exists = await conn.fetchval("SELECT to_regclass('twinlink_schema') IS NOT NULL")
    if not exists:
        return 0
    return int(await conn.fetchval("SELECT coalesce(max(version), 0) FROM twinlink_schema"))


async def applied_versions(conn: Connection) -> set[int]:
    """Every migration the database has had. A migration is applied when it is missing from
    this set, not when its number is above the highest: numbers are given out in ranges
    (history's below 10, metadata's from 10), so a lower one may ship after a higher one."""
    exists = await conn.fetchval("SELECT to_regclass('twinlink_schema') IS NOT NULL")
    if not exists:
        return set()
    return {int(row[0]) for row in await conn.fetch("SELECT version FROM twinlink_schema")}


async def migrate(conn: Connection, target: int | None = None) -> list[int]:
    """Apply pending migrations in order, each in its own transaction; those applied."""
    applied = []
    for version, name, sql in migrations():
        if target is not None and version > target:
            break
        async with conn.transaction():
            # Taken again per migration and held to its commit: a second node waits here,
            # then sees the version the first one wrote and skips the file.
            await conn.execute("SELECT pg_advisory_xact_lock($1)", _MIGRATION_LOCK)
            if version in await applied_versions(conn):
                continue
            await conn.execute(sql)
            await conn.execute(
                "CREATE TABLE IF NOT EXISTS twinlink_schema (version integer PRIMARY KEY, "
                "applied_at timestamptz NOT NULL DEFAULT now())"
            )
            await conn.execute("INSERT INTO twinlink_schema (version) VALUES ($1)", version)
        log.info("schema migrated", extra={"event": "migrate", "version": version, "file": name})
        applied.append(version)
    return applied


# The server is away, shutting down, restarting or out of resources: the same request may
# succeed later. Any other database error is a bug of ours, and stays as it is (a 500).
_UNAVAILABLE = (
    asyncpg.PostgresConnectionError,  # the connection failed or was lost
    asyncpg.OperatorInterventionError,  # shutdown, restart, "cannot connect now"
    asyncpg.InsufficientResourcesError,  # out of memory, too many connections
    asyncpg.InterfaceError,  # the connection closed under a query
    # a query on a connection whose server side ended while it was idle (the server's
    # FATAL message came between two queries): asyncpg's protocol is then in a state of
    # its own
    asyncpg.InternalClientError,
    OSError,  # refused, reset, unreachable
    TimeoutError,
)

# A name taken, or a row named that a request running at the same time deleted. Not every
# integrity error: history makes a partition when a row finds none (a check violation).
_CONFLICTS = (asyncpg.UniqueViolationError, asyncpg.ForeignKeyViolationError)


def translate(err: BaseException) -> BaseException:
    """`err` as the store's own error (chained to it) when it is the database's or the
    connection's; any other error as it is."""
    mapped: BaseException
    if isinstance(err, _CONFLICTS):
        # as SQLite's IntegrityError (sqlite/db.py): sending the request again answers it
        mapped = WriteConflictError()
    elif isinstance(err, asyncpg.CharacterNotInRepertoireError):
        mapped = InvalidInputError(NUL)
    elif isinstance(err, asyncpg.DiskFullError):
        mapped = StorageFullError(FULL)
    elif isinstance(err, _UNAVAILABLE):
        mapped = StorageError(UNREACHABLE)
    else:
        return err
    mapped.__cause__ = err
    return mapped


class PostgresDatabase:
    """The pool the stores of this backend share."""

    def __init__(self, dsn: str, *, max_connections: int = 10) -> None:
        self.dsn = dsn
        self.max_connections = max_connections
        self._pool: asyncpg.Pool | None = None

    async def open(self) -> None:
        try:
            pool = await asyncpg.create_pool(self.dsn, min_size=1, max_size=self.max_connections)
        except (asyncpg.PostgresError, *_UNAVAILABLE) as err:
            # the server's own words (refused, no such database, authentication failed)
            # say what to fix; the DSN is not repeated, it may hold a password
            raise StorageError(f"Cannot connect to PostgreSQL: {err}") from err
        try:
            async with pool.acquire() as conn:
                await migrate(conn)
        except BaseException:
            await pool.close()
            raise
        self._pool = pool

    async def close(self) -> None:
        if self._pool is not None:
            await self._pool.close()
            self._pool = None

    @property
    def pool(self) -> asyncpg.Pool:
        if self._pool is None:
            raise RuntimeError("the PostgreSQL store is not open")
        return self._pool

    @asynccontextmanager
    async def connection(self) -> AsyncIterator[Connection]:
        """A connection of the pool; the database's errors leave as the store's own."""
        try:
            async with self.pool.acquire() as conn:
                yield conn
        except (
            *_UNAVAILABLE,
            *_CONFLICTS,
            asyncpg.CharacterNotInRepertoireError,
        ) as err:
            raise translate(err) from err

    @asynccontextmanager
    async def transaction(self) -> AsyncIterator[Connection]:
        """A connection in one transaction: all of its writes land (durably) or none do."""
        async with self.connection() as conn, conn.transaction():
            yield conn
