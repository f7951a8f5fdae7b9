"""Deleting history: by age (retention), the dedupe record of old batches, and whole twins.

Each function deletes at most one chunk and returns how many rows it removed; the caller runs
it through the writer's group commit (`SqliteHistory.write`) until a chunk comes back short,
so one large deletion never holds the write lock long enough to stall ingest, and never
needs much more WAL than one chunk (once it is checkpointed, the WAL is reused).
"""

from __future__ import annotations

import sqlite3

# Deleting a block rewrites the pages holding its row and its two index entries; freed
# overflow pages only go on the free list. So a chunk touches at most ~3 pages a block: 1 000
# blocks are at most ~12 MB of WAL (measured: 8 MB for 2 000 blocks of 1 000-signal
# batches, the most scattered case), within the 16 MiB journal_size_limit (db.py).
CHUNK = 1_000


def delete_blocks_before(conn: sqlite3.Connection, cutoff_ns: int, chunk: int = CHUNK) -> int:
    """Blocks whose last sample is older than the cutoff (index `blocks_by_end`)."""
    cursor = conn.execute(
        "DELETE FROM blocks WHERE rowid IN (SELECT rowid FROM blocks WHERE t1 < ? LIMIT ?)",
        (cutoff_ns, chunk),
    )
    return cursor.rowcount


def delete_latest_before(conn: sqlite3.Connection, cutoff_ns: int) -> int:
    """Latest values older than the cutoff: they are history too."""
    return conn.execute("DELETE FROM latest WHERE t < ?", (cutoff_ns,)).rowcount


def delete_ingested_before(conn: sqlite3.Connection, cutoff_ns: int, chunk: int = CHUNK) -> int:
    """The record of batches stored before the cutoff (a resend after that is stored again)."""
    cursor = conn.execute(
        "DELETE FROM ingested WHERE (device_id, seq) IN "
        "(SELECT device_id, seq FROM ingested WHERE at_ns < ? LIMIT ?)",
        (cutoff_ns, chunk),
    )
    return cursor.rowcount


def delete_twin_blocks(conn: sqlite3.Connection, twin_id: int, chunk: int = CHUNK) -> int:
    """One chunk of the blocks of a twin's series."""
    cursor = conn.execute(
        "DELETE FROM blocks WHERE rowid IN (SELECT rowid FROM blocks WHERE series_id IN "
        "(SELECT id FROM series WHERE twin_id = ?) LIMIT ?)",
        (twin_id, chunk),
    )
    return cursor.rowcount


def delete_twin_series(conn: sqlite3.Connection, twin_id: int) -> int:
    """A twin's series with their latest values (and any blocks left, by cascade)."""
    return conn.execute("DELETE FROM series WHERE twin_id = ?", (twin_id,)).rowcount
