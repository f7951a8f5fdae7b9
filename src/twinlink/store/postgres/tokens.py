"""Shared tokens in PostgreSQL (`SharedTokens`, store/tokens.py): one row per service in
gateway_tokens. A refresh is one transaction holding an advisory lock named by the service
from the re-read of the row to the commit of the new token, so nodes refreshing together
queue on the lock: the first logs in, the others find its token (or its failure) when they
get the lock and return without a login."""

from __future__ import annotations

import asyncio
from datetime import datetime
from typing import Any

import asyncpg

from twinlink.domain.errors import StorageError, TwinlinkError
from twinlink.store.postgres.db import Connection, PostgresDatabase
from twinlink.store.tokens import Fetch, NewToken, SharedRefreshFailed, SharedToken

# Seconds from now on the database's clock: the nodes' clocks may disagree, the row's may not.
_READ = (
    "SELECT fingerprint, sealed, failed_at, failure, "
    "extract(epoch FROM renew_at - clock_timestamp())::float8 AS renew_in, "
    "extract(epoch FROM expires_at - clock_timestamp())::float8 AS expires_in "
    "FROM gateway_tokens WHERE service = $1"
)
# statement_timestamp() is when this statement began, before any wait for the lock: a login
# that failed after it is one this caller waited for.
_LOCK = (
    "SELECT statement_timestamp(), "
    "pg_advisory_xact_lock(hashtextextended('gateway_tokens:' || $1, 0))"
)
_STORE = (
    "INSERT INTO gateway_tokens (service, fingerprint, sealed, renew_at, expires_at) "
    "VALUES ($1, $2, $3, clock_timestamp() + make_interval(secs => $4), "
    "clock_timestamp() + make_interval(secs => $5)) "
    "ON CONFLICT (service) DO UPDATE SET fingerprint = excluded.fingerprint, "
    "sealed = excluded.sealed, renew_at = excluded.renew_at, expires_at = excluded.expires_at, "
    "failed_at = NULL, failure = NULL"
)
# A failure keeps the token of the same credentials (it may still work a while).
_FAILED = (
    "INSERT INTO gateway_tokens AS t (service, fingerprint, failed_at, failure) "
    "VALUES ($1, $2, clock_timestamp(), $3) "
    "ON CONFLICT (service) DO UPDATE SET failed_at = excluded.failed_at, "
    "failure = excluded.failure, fingerprint = excluded.fingerprint, "
    "sealed = CASE WHEN t.fingerprint = excluded.fingerprint THEN t.sealed END, "
    "renew_at = CASE WHEN t.fingerprint = excluded.fingerprint THEN t.renew_at END, "
    "expires_at = CASE WHEN t.fingerprint = excluded.fingerprint THEN t.expires_at END"
)


class PostgresTokens:
    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db
        # A refresh holds a connection for a login (or the wait for another node's), seconds
        # when an upstream is slow: a third of the pool at most, the rest for everything else.
        self._refreshing = asyncio.Semaphore(max(1, db.max_connections // 3))

    async def current(self, service: str, fingerprint: str) -> SharedToken | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(_READ, service)
        return _token(row, fingerprint)

    async def refresh_once(
        self, service: str, fingerprint: str, stale: bytes | None, fetch: Fetch, wait_s: float
    ) -> SharedToken:
        async with self._refreshing:
            return await self._refresh_once(service, fingerprint, stale, fetch, wait_s)

    async def _refresh_once(
        self, service: str, fingerprint: str, stale: bytes | None, fetch: Fetch, wait_s: float
    ) -> SharedToken:
        try:
            async with self.db.transaction() as conn:
                await conn.execute("SELECT set_config('lock_timeout', $1, true)",
                                   f"{max(1, round(wait_s * 1000))}ms")  # fmt: skip
                asked: datetime = await conn.fetchval(_LOCK, service)
                row = await conn.fetchrow(_READ, service)
                if row is not None and row["fingerprint"] == fingerprint:
                    failed_at = row["failed_at"]
                    if failed_at is not None and failed_at > asked:
                        raise SharedRefreshFailed(row["failure"] or "the login failed")
                    found = _token(row, fingerprint)
                    if found is not None and found.sealed != stale and found.renew_in_s > 0:
                        return found  # another node logged in while this one waited
                outcome = await _login(conn, service, fingerprint, fetch)
        except asyncpg.LockNotAvailableError as err:
            raise StorageError(
                f"another node's login for this service did not finish within {wait_s:g} s"
            ) from err
        if isinstance(outcome, TwinlinkError):
            raise outcome  # once its record committed, for the nodes that waited for it
        return outcome


async def _login(
    conn: Connection, service: str, fingerprint: str, fetch: Fetch
) -> SharedToken | TwinlinkError:
    """The token `fetch` got, stored; or its error, recorded (raising it here would roll the
    record back)."""
    try:
        new: NewToken = await fetch()
    except TwinlinkError as err:
        # NUL: PostgreSQL's text cannot hold one; the upstream's words may.
        said = str(err).replace("\x00", "")[:500]
        await conn.execute(_FAILED, service, fingerprint, said)
        return err
    await conn.execute(_STORE, service, fingerprint, new.sealed,
                       float(new.renew_after_s), float(new.life_s))  # fmt: skip
    return SharedToken(new.sealed, new.renew_after_s, new.life_s)


def _token(row: Any, fingerprint: str) -> SharedToken | None:
    if row is None or row["fingerprint"] != fingerprint or row["sealed"] is None:
        return None
    return SharedToken(bytes(row["sealed"]), float(row["renew_in"]), float(row["expires_in"]))
