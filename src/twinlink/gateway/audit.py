"""The gateway's audit log: every answered request on a service path, written in batches (one
transaction every half second at most), kept for `audit_days`."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time

from twinlink.domain.errors import StorageError
from twinlink.domain.records import AuditEntry
from twinlink.store.base import MetadataStore

log = logging.getLogger("twinlink.gateway")
FLUSH_S = 0.5
# Entries waiting for the disk beyond this are dropped (and counted): a slow disk must not
# make the gateway run out of memory.
MAX_PENDING = 100_000


class AuditLog:
    def __init__(self, store: MetadataStore, keep_days: float) -> None:
        self.store = store
        self.keep_days = keep_days
        self._pending: list[AuditEntry] = []
        self._wake = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self.written = 0
        self.dropped = 0

    def record(self, entry: AuditEntry) -> None:
        if len(self._pending) >= MAX_PENDING:
            self.dropped += 1
            return
        self._pending.append(entry)
        self._wake.set()

    def start(self) -> None:
        self._task = asyncio.create_task(self._run(), name="gateway-audit")

    async def stop(self) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
            self._task = None
        await self.flush()

    async def flush(self) -> None:
        """Write what is pending now (also what tests and the API call before reading)."""
        batch, self._pending = self._pending, []
        if not batch:
            return
        keep_after = 0 if self.keep_days <= 0 else time.time_ns() - int(self.keep_days * 86400e9)
        try:
            await self.store.add_audit(batch, keep_after)
            self.written += len(batch)
        except StorageError:  # a full disk: the store logs that once a minute
            self.dropped += len(batch)
        except Exception:
            self.dropped += len(batch)
            log.exception("gateway audit write failed", extra={"event": "audit_failed"})

    async def _run(self) -> None:
        while True:
            await self._wake.wait()
            self._wake.clear()
            await self.flush()
            await asyncio.sleep(FLUSH_S)  # batches what arrives meanwhile into one commit
