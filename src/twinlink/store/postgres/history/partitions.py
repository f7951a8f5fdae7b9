"""The time ranges of the partitioned `samples` table, made as batches need them.

Each partition holds 2**51 ns (about 26 days) of sample times, aligned to the epoch: few
enough partitions for years of history, small enough for retention to drop whole ones. A
partition is made in a short transaction of its own before the batch that needs it is
written (its DDL would otherwise lock `samples` for the batch's whole transaction), under an
advisory lock, so writers on several nodes make each once.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterable

import asyncpg

from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.store.postgres.db import Connection

WIDTH_BITS = 51
_LOCK_BASE = 0x7477_6C6E_6B01_0000  # + the partition's number: one advisory lock each


def key_of(t: int) -> int:
    """The number of the partition that holds time `t` (negative before the epoch)."""
    return t >> WIDTH_BITS


def bounds(key: int) -> tuple[str, str]:
    """The partition's range as SQL literals, FROM inclusive, TO exclusive; the last one is
    open above (its end would not fit in a bigint)."""
    low = key << WIDTH_BITS
    high = (key + 1) << WIDTH_BITS
    return str(max(low, MIN_TIME)), "MAXVALUE" if high > MAX_TIME else str(high)


def name(key: int) -> str:
    return f"samples_p{key}" if key >= 0 else f"samples_m{-key}"


def keys_of(times: Iterable[int]) -> set[int]:
    return {t >> WIDTH_BITS for t in times}


async def create(conn: Connection, key: int) -> None:
    """Make the partition unless it exists (another node may make it at the same time)."""
    low, high = bounds(key)
    async with conn.transaction():
        await conn.execute("SELECT pg_advisory_xact_lock($1)", _LOCK_BASE + key)
        # IF NOT EXISTS and the lock make a second maker skip; the suppress is for a maker
        # that does not take the lock (an older version of this code, a person)
        with contextlib.suppress(asyncpg.DuplicateTableError):
            await conn.execute(
                f"CREATE TABLE IF NOT EXISTS {name(key)} PARTITION OF samples "
                f"FOR VALUES FROM ({low}) TO ({high})"
            )


async def existing(conn: Connection) -> dict[int, str]:
    """{partition number: table name} of the partitions there are."""
    rows = await conn.fetch(
        "SELECT c.relname FROM pg_inherits i JOIN pg_class c ON c.oid = i.inhrelid "
        "WHERE i.inhparent = 'samples'::regclass"
    )
    found = {}
    for (relname,) in rows:
        number = relname.removeprefix("samples_")
        key = int(number[1:]) * (1 if number[0] == "p" else -1)
        found[key] = relname
    return found
