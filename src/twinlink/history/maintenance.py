"""Keeping history tidy in the background: retention, the dedupe record, deleted twins.

Every 30 seconds, the store compacts what small batches left behind (SQLite: series that got
small blocks have them merged, store/sqlite/history/compact.py).
Every 10 minutes (and once at start): samples older than `history_retention_days` are deleted
when it is more than 0, and the record of stored batches (which makes a resent batch a
duplicate) forgets batches older than 7 days. When twins are deleted, their history goes too.
Every deletion runs in chunks through the writer's group commit, so ingest keeps flowing;
after a round that deleted something the WAL is checkpointed and truncated, so the space the
deletion needed is handed back at once (`reclaim_space`; docs/config.md, "Disk space").

A full disk makes these fail as every other write does (StorageError): the store counts and
logs that once a minute (store/sqlite/faults.py), so the failures are not logged again here.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable

from twinlink.domain.errors import StorageError
from twinlink.store.history import HistoryUpkeep

log = logging.getLogger("twinlink.history")

EVERY_S = 600.0
COMPACT_EVERY_S = 30.0
DAY_NS = 86_400 * 10**9
DEDUPE_DAYS = 7


class HistoryMaintenance:
    def __init__(
        self,
        history: HistoryUpkeep,
        retention_days: float,
        every_s: float = EVERY_S,
        compact_every_s: float = COMPACT_EVERY_S,
        clock: Callable[[], int] = time.time_ns,
    ) -> None:
        self.history = history
        self.retention_days = retention_days
        self.every_s = every_s
        self.clock = clock
        self._loop_task: asyncio.Task[None] | None = None
        self._compact_task: asyncio.Task[None] | None = None
        self.compact_every_s = compact_every_s
        self._deletions: set[asyncio.Task[None]] = set()

    def start(self) -> None:
        self._loop_task = asyncio.create_task(self._run(), name="history-maintenance")
        self._compact_task = asyncio.create_task(self._compact(), name="history-compaction")

    async def stop(self) -> None:
        for task in (self._loop_task, self._compact_task):
            if task is not None:
                task.cancel()
                await asyncio.gather(task, return_exceptions=True)
        self._loop_task = self._compact_task = None
        # A twin's deletion that has begun is finished: its history must not outlive it.
        await asyncio.gather(*self._deletions, return_exceptions=True)

    async def _run(self) -> None:
        while True:
            try:
                await self.run_once()
            except StorageError:
                pass  # counted and logged by the store; the next round tries again
            except Exception:
                log.exception("history maintenance failed", extra={"event": "history_retention"})
            await asyncio.sleep(self.every_s)

    async def _compact(self) -> None:
        while True:
            await asyncio.sleep(self.compact_every_s)
            try:
                done = await self.history.compact()
            except StorageError:
                continue  # counted and logged by the store
            except Exception:
                log.exception("history compaction failed", extra={"event": "history_compact"})
                continue
            if done.before:
                log.debug(
                    "history compacted",
                    extra={"event": "history_compact", "before": done.before,
                           "after": done.after},
                )  # fmt: skip

    async def run_once(self) -> dict[str, int]:
        """One round; returns what was deleted."""
        now = self.clock()
        done = {"blocks": 0, "batches": 0}
        if self.retention_days > 0:
            cutoff = now - int(self.retention_days * DAY_NS)
            done["blocks"] = await self.history.delete_before(cutoff)
        done["batches"] = await self.history.forget_ingested_before(now - DEDUPE_DAYS * DAY_NS)
        if any(done.values()):
            await self.history.reclaim_space()
            log.info("history retention", extra={"event": "history_retention", **done})
        return done

    async def sweep_orphans(self, existing: set[int]) -> list[int]:
        """Delete the history of twins that no longer exist (a crash between deleting a twin
        and deleting its history leaves such series behind). Call once at start."""
        orphans = sorted(await self.history.twin_ids() - existing)
        if orphans:
            self.twins_deleted(orphans)
        return orphans

    def twins_deleted(self, twin_ids: list[int]) -> None:
        """A registry listener: delete the history of these twins, in the background."""
        for twin_id in twin_ids:
            task = asyncio.create_task(self._delete_twin(twin_id), name=f"history-delete-{twin_id}")
            self._deletions.add(task)
            task.add_done_callback(self._deletions.discard)

    async def _delete_twin(self, twin_id: int) -> None:
        try:
            blocks = await self.history.delete_twin(twin_id)
        except StorageError:  # counted and logged by the store
            log.warning(
                "a deleted twin's history stays until the next start (storage failed)",
                extra={"event": "history_delete_failed", "twin_id": twin_id},
            )
            return
        except Exception:
            log.exception(
                "deleting a twin's history failed",
                extra={"event": "history_delete_failed", "twin_id": twin_id},
            )
            return
        log.info(
            "twin history deleted",
            extra={"event": "history_deleted", "twin_id": twin_id, "blocks": blocks},
        )
