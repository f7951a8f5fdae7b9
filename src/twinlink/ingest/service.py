"""From a device's batch to durable history and the bus, with its ack.

The path of one batch: read and check it against the twin's interface (`domain.samples`),
store it in history (group commit; a `seq` already stored is not stored twice), then publish
it on the bus for live clients and processors, then answer the device. Live clients therefore
only ever see samples that are durable, and a device is acknowledged only once its batch is
both stored and on the bus (docs/decisions/0013): when the bus fails after the commit, the
device gets an error (503), sends the batch again, and the resend publishes what was stored.
"""

from __future__ import annotations

import asyncio
import logging
import time
from dataclasses import dataclass
from functools import partial
from typing import Any

from twinlink.bus import Bus, samples_subject
from twinlink.domain.errors import StorageError
from twinlink.domain.merge import merge_parts
from twinlink.domain.records import Device
from twinlink.domain.samples import (
    MAX_REPORTED_REJECTIONS,
    ReadBatch,
    SampleBatch,
    Schema,
    read_batch,
    schema_from_interface,
)
from twinlink.registry.cache import GenerationCache
from twinlink.registry.service import RegistryService
from twinlink.store.history import HistoryWriterStore

log = logging.getLogger("twinlink.ingest")
OUTPUT_LOG_EVERY_S = 60.0


@dataclass(slots=True)
class Ack:
    seq: int
    accepted: int
    rejected: list[dict[str, Any]]
    rejected_count: int
    server_timed: int
    dropped: int
    duplicate: bool

    def message(self) -> dict[str, Any]:
        return {
            "type": "ack",
            "seq": self.seq,
            "accepted": self.accepted,
            "rejected": self.rejected,
            "rejected_count": self.rejected_count,
            "server_timed": self.server_timed,
            "dropped": self.dropped,
            "duplicate": self.duplicate,
        }


class IngestService:
    def __init__(self, registry: RegistryService, history: HistoryWriterStore, bus: Bus) -> None:
        self.registry = registry
        self.history = history
        self.bus = bus
        self._storing: set[asyncio.Future[bool]] = set()
        # The interface rules per twin, dropped on any registry change (and not kept when a
        # change raced the read).
        self._schemas: GenerationCache[int, Schema] = GenerationCache(lambda: registry.generation)
        self.samples_accepted = 0
        self.samples_rejected = 0
        self.batches_duplicate = 0
        self.outputs_not_stored = 0  # processor output batches the store refused
        self._refusals: dict[tuple[int, str], tuple[float, int]] = {}  # last logged, since

    async def schema_for(self, twin_id: int) -> Schema:
        schema = self._schemas.get(twin_id)
        if schema is None:
            read_at = self._schemas.generation()
            parts = await self.registry.store.get_parts(twin_id)
            interface = merge_parts(parts).get("interface") if parts else None
            schema = schema_from_interface(interface if isinstance(interface, dict) else None)
            self._schemas.keep(twin_id, schema, read_at)
        return schema

    async def ingest(self, device: Device, body: Any) -> Ack:
        """Store one batch from `device`. Raises BatchError when it cannot be read at all,
        TooManySignalsError when it would give its stream too many signals (nothing of it is
        stored in either case), StorageError when the disk refused it, UnavailableError
        (KafkaBusError) when the bus did not take it (send it again in both cases)."""
        received_ns = time.time_ns()
        schema = await self.schema_for(device.twin_id)
        read = read_batch(body, schema, received_ns)
        duplicate = False
        if read.times:
            batch = SampleBatch(
                twin_id=device.twin_id,
                twin=device.twin_slug,
                stream=read.stream,
                times=read.times,
                values=read.values,
                received_ns=received_ns,
                source=device.name,
                seq=read.seq,
            )
            duplicate = not await self.history.append(batch, device.id)
            # A resend of a batch stored before whose publish failed (the bus away after the
            # commit, or the node stopped between the two) is published now: the device was
            # not acknowledged, so nothing else will put it on the bus. Only duplicates ask.
            if not duplicate or await self.history.unpublished(device.id, read.seq):
                await self.bus.publish(samples_subject(device.twin_id, read.stream), batch)
                self.history.published(device.id, read.seq)
        return self._ack(read, duplicate)

    async def publish(self, batch: SampleBatch) -> None:
        """Store and publish samples made inside the platform (processors, simulators)."""
        await self.history.append(batch)
        await self.bus.publish(samples_subject(batch.twin_id, batch.stream), batch)

    async def publish_first(self, batch: SampleBatch) -> None:
        """Samples the platform made from others (processor outputs): on the bus at once and
        stored by the next group commit, so live views and chained processors do not wait for
        the disk. Stores happen in call order."""
        stored = asyncio.ensure_future(self.history.append(batch))
        self._storing.add(stored)
        stored.add_done_callback(partial(self._stored, batch))
        await self.bus.publish(samples_subject(batch.twin_id, batch.stream), batch)

    def _stored(self, batch: SampleBatch, task: asyncio.Future[bool]) -> None:
        self._storing.discard(task)
        if task.cancelled() or task.exception() is None:
            return
        self.outputs_not_stored += 1
        err = task.exception()
        if isinstance(err, StorageError):
            return  # counted and logged (once a minute) by the store
        # A processor whose output is refused (too many signals) sends the next batch a
        # moment later: one line per stream a minute, not one per batch.
        key = (batch.twin_id, batch.stream)
        now = time.monotonic()
        last, missed = self._refusals.get(key, (-OUTPUT_LOG_EVERY_S, 0))
        if now - last < OUTPUT_LOG_EVERY_S:
            self._refusals[key] = (last, missed + 1)
            return
        self._refusals[key] = (now, 0)
        log.error(
            "output of %s not stored (stream %r of twin %r): %s%s", batch.source, batch.stream,
            batch.twin, err, f" ({missed} more since the last report)" if missed else "",
            extra={"event": "output_not_stored", "twin": batch.twin, "stream": batch.stream},
        )  # fmt: skip

    def _ack(self, read: ReadBatch, duplicate: bool) -> Ack:
        if duplicate:
            self.batches_duplicate += 1
        else:
            self.samples_accepted += len(read.times)
        self.samples_rejected += len(read.rejected)
        return Ack(
            seq=read.seq,
            accepted=0 if duplicate else len(read.times),
            rejected=[
                {"index": r.index, "reason": r.reason}
                for r in read.rejected[:MAX_REPORTED_REJECTIONS]
            ],
            rejected_count=len(read.rejected),
            server_timed=read.server_timed,
            dropped=read.dropped,
            duplicate=duplicate,
        )
