"""Leases in PostgreSQL (`LeaseStore`, store/leases.py): one row per name, expiry on the
database's clock. Taking and renewing a batch of leases is one statement: a row another
holder has and that has not expired is left as it is (and not returned)."""

from __future__ import annotations

from twinlink.store.postgres.db import PostgresDatabase

# ON CONFLICT re-reads a row another node is changing at the same time once that node
# commits, so two nodes taking one free lease together leave it with exactly one of them.
_ACQUIRE = (
    "INSERT INTO leases (name, holder, expires_at) "
    "SELECT n, $2, now() + make_interval(secs => $3) FROM unnest($1::text[]) AS n "
    "ON CONFLICT (name) DO UPDATE SET holder = excluded.holder, expires_at = excluded.expires_at "
    "WHERE leases.holder = excluded.holder OR leases.expires_at <= now() "
    "RETURNING name"
)


class PostgresLeases:
    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db

    async def acquire(self, names: list[str], holder: str, ttl_s: float) -> set[str]:
        if not names:
            return set()
        async with self.db.connection() as conn:
            rows = await conn.fetch(_ACQUIRE, names, holder, float(ttl_s))
        return {row[0] for row in rows}

    async def release(self, names: list[str], holder: str) -> None:
        async with self.db.connection() as conn:
            await conn.execute(
                "DELETE FROM leases WHERE holder = $1 AND name = ANY($2::text[])", holder, names
            )

    async def held(self, holder: str) -> set[str]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "SELECT name FROM leases WHERE holder = $1 AND expires_at > now()", holder
            )
        return {row[0] for row in rows}
