"""Leases in PostgreSQL (`LeaseStore`, store/leases.py): one row per name, expiry on the
database's clock. Taking and renewing a batch of leases is one statement: a row another
holder has and that has not expired is left as it is (and not returned). Positions
(lease_positions) are saved in one statement too, only for the leases the holder has now."""

from __future__ import annotations

from twinlink.store.leases import Position
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


# The lease is checked in the same statement, so a node that lost its lease (paused past its
# TTL) cannot write over the position of the node that took the item over; in one stream a
# position only moves forward (a resumed node's older one is left as it is).
_SAVE_POSITIONS = (
    "INSERT INTO lease_positions AS p (name, stream, t) "
    "SELECT n, s, t FROM unnest($1::text[], $2::text[], $3::bigint[]) AS x (n, s, t) "
    "JOIN leases l ON l.name = x.n AND l.holder = $4 AND l.expires_at > now() "
    "ON CONFLICT (name) DO UPDATE SET stream = excluded.stream, saved_at = now(), "
    "t = CASE WHEN p.stream = excluded.stream THEN greatest(p.t, excluded.t) ELSE excluded.t END"
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

    async def save_positions(self, positions: dict[str, Position], holder: str) -> None:
        if not positions:
            return
        names = list(positions)
        streams = [positions[n].stream for n in names]
        times = [positions[n].t for n in names]
        async with self.db.connection() as conn:
            await conn.execute(_SAVE_POSITIONS, names, streams, times, holder)

    async def positions(self, names: list[str]) -> dict[str, Position]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "SELECT name, stream, t FROM lease_positions WHERE name = ANY($1::text[])", names
            )
        return {row[0]: Position(row[1], row[2]) for row in rows}

    async def forget_positions(self, names: list[str]) -> None:
        async with self.db.connection() as conn:
            await conn.execute("DELETE FROM lease_positions WHERE name = ANY($1::text[])", names)
