"""Which stored device batches reached the bus: `ingested.published`.

A device's batch is acknowledged once it is committed AND published (docs/decisions/0013).
When the publish fails after the commit (Kafka down or slow), the device is answered 503 and
sends the batch again; the resend finds its (device, seq) stored and, through `unpublished`,
that it still has to go on the bus. The writer inserts each row as not published; the mark
that it was comes after the publish, off the ack's path: marks are collected and written
together, one UPDATE for all that came in while the previous one ran, without waiting for
the commit to reach the disk. A mark that is lost (the node stopped, the database away) only
means a resend publishes the batch again: a duplicate on the bus, never a sample missing.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging

from twinlink.domain.errors import StorageError
from twinlink.store.postgres.db import PostgresDatabase

log = logging.getLogger("twinlink.store")

_MARK = (
    "UPDATE ingested i SET published = true FROM unnest($1::bigint[], $2::bigint[]) "
    "AS m(device_id, seq) WHERE i.device_id = m.device_id AND i.seq = m.seq"
)


class PublishedMarks:
    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db
        self._pending: set[tuple[int, int]] = set()  # to write
        self._in_flight: set[tuple[int, int]] = set()  # being written
        self._writing: asyncio.Task[None] | None = None
        self.lost = 0  # marks not written (the database failed them): resends republish

    def mark(self, device_id: int, seq: int) -> None:
        """Note that (device, seq) is on the bus; written soon after, with others."""
        self._pending.add((device_id, seq))
        if self._writing is None:
            self._writing = asyncio.create_task(self._write(), name="history-published-marks")

    async def unpublished(self, device_id: int, seq: int) -> bool:
        """Whether (device, seq) is stored but not known to be on the bus."""
        if (device_id, seq) in self._pending or (device_id, seq) in self._in_flight:
            return False  # published by this node, its mark not yet committed
        async with self.db.connection() as conn:
            found = await conn.fetchval(
                "SELECT NOT published FROM ingested WHERE device_id = $1 AND seq = $2",
                device_id, seq,
            )  # fmt: skip
        return bool(found)

    async def close(self) -> None:
        """Write the marks still pending (a mark lost here is harmless, see the docstring)."""
        if self._writing is not None:
            with contextlib.suppress(Exception):
                await self._writing

    async def _write(self) -> None:
        try:
            while self._pending:
                marks = self._in_flight = self._pending
                self._pending = set()
                devices, seqs = zip(*marks, strict=True)
                try:
                    async with self.db.transaction() as conn:
                        # A lost mark costs a duplicate on the bus at most: no disk wait for it.
                        await conn.execute("SET LOCAL synchronous_commit TO off")
                        await conn.execute(_MARK, list(devices), list(seqs))
                except Exception as err:  # nobody awaits this task: it logs its own failures
                    self.lost += len(marks)
                    log.warning(
                        "%d published marks not written (a resend of those batches publishes "
                        "them again): %s", len(marks), err,
                        extra={"event": "published_marks_lost", "count": len(marks)},
                        exc_info=not isinstance(err, StorageError),  # anything else is a bug
                    )  # fmt: skip
                finally:
                    self._in_flight = set()
        finally:
            self._writing = None
