"""One processor hosted on this node: its supervised worker, fed from its source stream on the
bus (after a catch-up from history on a shared store, catchup.py), and how far it got."""

from __future__ import annotations

import asyncio
import time
from dataclasses import dataclass
from typing import Any

from twinlink.bus import Bus, samples_subject
from twinlink.domain.records import ProcessorRecord
from twinlink.domain.samples import SampleBatch
from twinlink.processors.catchup import CatchUp
from twinlink.processors.checks import spec_of
from twinlink.processors.convert import to_columns
from twinlink.processors.spec import ProcessorSpec
from twinlink.processors.supervisor import Supervisor
from twinlink.store.history import HistoryReadStore
from twinlink.store.leases import Claims, Position


@dataclass(slots=True)
class Hosted:
    record: ProcessorRecord
    supervisor: Supervisor
    unsubscribe: Any = None
    catch_up: CatchUp | None = None  # on a shared store: its catch-up, then its position
    catching_up: asyncio.Task[None] | None = None
    saved: Position | None = None  # the position last saved
    _wanted: tuple[object, object, list[str] | None] = (None, None, None)

    def wanted(self) -> list[str] | None:
        """The source signals the running blueprint reads (None: all, until it has said);
        worked out again only when the spec or the running blueprint changed."""
        spec, info = self.record.spec, self.supervisor.info
        if self._wanted[0] is not spec or self._wanted[1] is not info:
            self._wanted = (spec, info, _wanted(spec_of(self.record), info))
        return self._wanted[2]

    def position(self) -> Position | None:
        """How far it got in its source stream (None: not known yet, or not kept)."""
        start = self.catch_up.start if self.catch_up is not None else None
        done = self.supervisor.processed_t
        if start is None or done is None or done <= start.t:
            return start
        return Position(start.stream, done)

    def start(self) -> None:
        """Start the worker, and the catch-up when there is one: subscribed before, so nothing
        published from now on is missed."""
        self.supervisor.start()
        if self.catch_up is not None:
            self.catching_up = asyncio.create_task(self.catch_up.run())

    async def stop(self) -> None:
        self.unsubscribe()
        if self.catching_up is not None:
            self.catching_up.cancel()
            await asyncio.gather(self.catching_up, return_exceptions=True)
        await self.supervisor.stop()


def subscribed(
    record: ProcessorRecord,
    supervisor: Supervisor,
    bus: Bus,
    catch_up_from: tuple[Claims, HistoryReadStore] | None,
) -> Hosted:
    """The processor subscribed to its source stream (not started); with `catch_up_from`,
    the live batches are held until it has caught up from history."""
    hosted = Hosted(record, supervisor)

    def feed(batch: SampleBatch) -> None:
        supervisor.feed(to_columns(batch, hosted.wanted()), time.perf_counter())

    def on_batch(subject: str, batch: object) -> None:
        if isinstance(batch, SampleBatch):
            if hosted.catch_up is not None and not (batch := hosted.catch_up.take(batch)):
                return  # held back until the catch-up is done, or replayed already
            feed(batch)

    source = spec_of(record).source
    if catch_up_from is not None:
        claims, history = catch_up_from
        hosted.catch_up = CatchUp(
            record.id, record.twin_id, source, claims, history, feed,
            lambda b: supervisor.feed_in_turn(to_columns(b, hosted.wanted())),
            supervisor.on_events,
        )  # fmt: skip
    hosted.unsubscribe = bus.subscribe(samples_subject(record.twin_id, source), on_batch)
    return hosted


async def save_positions(claims: Claims, hosted: list[Hosted]) -> None:
    """How far the processors got, for the node that runs them next (those that moved)."""
    moved = {h.record.id: (h, p) for h in hosted if (p := h.position()) not in (None, h.saved)}
    if await claims.save_positions({pid: p for pid, (_, p) in moved.items() if p is not None}):
        for h, p in moved.values():
            h.saved = p


def _wanted(spec: ProcessorSpec, info: dict[str, Any]) -> list[str] | None:
    """The source signals a running blueprint reads (None: all, until it has said)."""
    inputs = info.get("inputs")
    if not inputs:
        return None
    maps = spec.input_maps()
    return list(dict.fromkeys(maps[i].signal if i in maps else i for i in inputs))
