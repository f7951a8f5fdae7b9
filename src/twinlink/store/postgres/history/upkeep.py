"""Deleting PostgreSQL history: by age (retention), the dedupe record of old batches, whole
twins. Partitions entirely older than a cutoff are dropped (no row by row deletion, no
bloat); the rest of the samples before it are deleted from the one partition that holds it.
The counts are of samples (this backend's pieces of storage)."""

from __future__ import annotations

from twinlink.store.postgres.db import Connection
from twinlink.store.postgres.history import partitions

# A signal's summary again from what is left of its samples (after a deletion).
_RESUMMARIZE = (
    "UPDATE series s SET n = coalesce(a.n, 0), first_t = a.first_t, last_t = a.last_t "
    "FROM (SELECT se.id, x.n, x.first_t, x.last_t FROM series se LEFT JOIN LATERAL "
    "(SELECT count(*) AS n, min(t) AS first_t, max(t) AS last_t FROM samples "
    "WHERE stream_id = se.stream_id AND series_id = se.id) x ON true "
    "WHERE se.first_t < $1) a WHERE s.id = a.id"
)


async def delete_before(conn: Connection, cutoff_ns: int) -> int:
    """Samples older than the cutoff, in one transaction; how many."""
    deleted = 0
    async with conn.transaction():
        for key, table in sorted((await partitions.existing(conn)).items()):
            _, high = partitions.bounds(key)
            if high != "MAXVALUE" and int(high) <= cutoff_ns:
                deleted += int(await conn.fetchval(f"SELECT count(*) FROM {table}"))
                await conn.execute(f"DROP TABLE {table}")
        status = await conn.execute("DELETE FROM samples WHERE t < $1", cutoff_ns)
        deleted += int(status.split()[-1])
        await conn.execute("DELETE FROM latest WHERE t < $1", cutoff_ns)
        await conn.execute(_RESUMMARIZE, cutoff_ns)
    return deleted


async def forget_ingested_before(conn: Connection, cutoff_ns: int) -> int:
    status = await conn.execute("DELETE FROM ingested WHERE at_ns < $1", cutoff_ns)
    return int(status.split()[-1])


async def delete_twin(conn: Connection, twin_id: int) -> int:
    """A twin's samples, series, latest values and streams; how many samples."""
    async with conn.transaction():
        status = await conn.execute(
            "DELETE FROM samples WHERE stream_id IN (SELECT id FROM streams WHERE twin_id = $1)",
            twin_id,
        )
        await conn.execute("DELETE FROM streams WHERE twin_id = $1", twin_id)  # cascades
    return int(status.split()[-1])
