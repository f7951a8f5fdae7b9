"""A processor that starts on a shared store first catches up, from history, on what it missed.

On PostgreSQL several nodes share the processors: each runs on the node holding its lease
(store/leases.py) and reads its source stream live from the bus. When that node dies, the
batches stored until another node takes the lease over (up to TTL_S + RENEW_S) reach no
processor on the bus. So the running node saves the processor's *position* with each lease
renewal (the newest source sample time its worker has answered for, Supervisor.processed_t),
and whichever node starts the processor next:

1. subscribes to the source stream first, holding the live batches back;
2. reads the position (none: the processor never ran, and its position becomes the newest
   time stored now, saved at once: what came before it started is not its input);
3. replays from history the source samples after the position, in time order;
4. hands the held live batches over, leaving out the samples the replay had (a batch stored
   before the replay read it and published after the subscription is in both), then the
   live ones as they come; for TAIL_S more a live batch with samples no later than the
   replay's last is checked against it too (a batch stored before the replay read it can
   reach this node over the bus later).

Bounded: at most MAX_REPLAY samples (the newest; the older ones are skipped) and none older
than MAX_AGE_NS before the stream's newest, each cut logged and recorded as a processor
event; at most MAX_REPLAY live samples are held meanwhile (the oldest dropped, as a worker's
queue drops them; logged and counted in the event). Samples are matched by time and values:
two samples alike in both, one replayed and one live, count as one (harmless: alike input).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections import Counter, deque
from collections.abc import Awaitable, Callable, Hashable
from typing import Any

from twinlink.domain.errors import NotFoundError, TwinlinkError
from twinlink.domain.history import MAX_TIME
from twinlink.domain.samples import SampleBatch
from twinlink.processors.supervisor import EventTuple
from twinlink.store.history import HistoryReadStore
from twinlink.store.leases import TTL_S, Claims, Position

log = logging.getLogger("twinlink.processors")

MAX_REPLAY = 100_000  # samples replayed at most (the newest of those missed)
MAX_AGE_NS = 600 * 10**9  # nor any older than this before the stream's newest sample
PAGE = 10_000  # rows read from history at once
TAIL_S = TTL_S  # how long live batches are still checked against the replay

Key = tuple[int, frozenset[tuple[str, Hashable]]]


def _key(t: int, values: dict[str, Any]) -> Key:
    return t, frozenset(values.items())


def _ns_iso(t: int) -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(t // 10**9))


class CatchUp:
    """The catch-up of one processor on one node, from its start until it reads live only."""

    def __init__(
        self,
        processor_id: int,
        twin_id: int,
        stream: str,
        claims: Claims,
        history: HistoryReadStore,
        feed: Callable[[SampleBatch], None],
        replay: Callable[[SampleBatch], Awaitable[None]],
        on_events: Callable[[list[EventTuple]], None],
    ) -> None:
        self.processor_id, self.twin_id, self.stream = processor_id, twin_id, stream
        self.claims, self.history = claims, history
        self.feed, self.replay, self.on_events = feed, replay, on_events
        self.start: Position | None = None  # where the processor starts (saved when new)
        self._held: deque[SampleBatch] | None = deque()  # live batches held (None: live)
        self._held_samples = 0
        self.dropped = 0  # held live samples dropped (over MAX_REPLAY while catching up)
        self._replayed: Counter[Key] = Counter()
        self._last_replayed: int | None = None
        self._tail_until = 0.0

    def take(self, batch: SampleBatch) -> SampleBatch | None:
        """A live batch: None when held back (or all replayed already), else what to feed."""
        if self._held is not None:
            self._held.append(batch)
            self._held_samples += len(batch)
            while self._held_samples > MAX_REPLAY and len(self._held) > 1:  # as Supervisor.feed
                self._held_samples -= len(old := self._held.popleft())
                self.dropped += len(old)
            return None
        if not self._replayed or self._last_replayed is None:
            return batch
        if time.monotonic() > self._tail_until:
            self._replayed.clear()  # the tail is over
            return batch
        if not batch.times or min(batch.times) > self._last_replayed:  # cheap: none can have been
            return batch
        return self._unreplayed(batch)

    @property
    def live(self) -> bool:
        return self._held is None

    async def run(self) -> None:
        """Replay what was missed, then hand the held batches over and go live. A failure to
        read history is logged and recorded; the processor then goes on live from there."""
        try:
            await self._replay_missed()
        except Exception as err:  # the processor must go live whatever the replay met
            message = f"could not catch up from history, going on live: {err}"
            log.warning("processor %d %s", self.processor_id, message,
                        exc_info=not isinstance(err, TwinlinkError),
                        extra={"event": "processor_catch_up_failed"})  # fmt: skip
            self.on_events([("catch_up_failed", message, time.time_ns(), {})])
        finally:
            self._go_live()

    def _go_live(self) -> None:
        held, self._held = self._held or deque(), None
        if self.dropped:
            log.warning("processor %d: %d live samples dropped while it caught up",
                        self.processor_id, self.dropped,
                        extra={"event": "processor_catch_up_dropped"})  # fmt: skip
        self._tail_until = time.monotonic() + TAIL_S
        for batch in held:
            left = self._unreplayed(batch) if self._replayed else batch
            if left is not None:
                self.feed(left)

    def _unreplayed(self, batch: SampleBatch) -> SampleBatch | None:
        keep = []
        for i, (t, values) in enumerate(zip(batch.times, batch.values, strict=True)):
            key = _key(t, values)
            left = self._replayed.get(key, 0)
            if left > 1:
                self._replayed[key] = left - 1
            elif left == 1:
                del self._replayed[key]  # all matched: the tail ends early
            else:
                keep.append(i)
        if len(keep) == len(batch):
            return batch
        if not keep:
            return None
        times = [batch.times[i] for i in keep]
        return dataclasses.replace(batch, times=times, values=[batch.values[i] for i in keep])

    async def _replay_missed(self) -> None:
        extent = await self._extent()
        position = await self.claims.position(self.processor_id)
        if position is None or position.stream != self.stream:  # never ran on this input
            self.start = Position(self.stream, extent[1] if extent else -1)
            # Saved now, not with the next renewal: its node killed before then leaves the
            # next one a position to replay from.
            await self.claims.save_positions({self.processor_id: self.start})
            return
        self.start = position
        if extent is None or extent[1] <= position.t:
            return  # nothing stored after it
        after = max(position.t, extent[1] - MAX_AGE_NS)
        rows, skipped = await self._read(after + 1)
        if not rows:
            return
        first, last = rows[0]["time"], rows[-1]["time"]
        for i in range(0, len(rows), PAGE):
            page = rows[i : i + PAGE]
            await self.replay(self._batch(page))
            self._replayed.update(_key(r["time"], r["values"]) for r in page)
        self._last_replayed = last
        self._report(len(rows), skipped, position.t, after, first, last)

    async def _extent(self) -> tuple[int, int] | None:
        try:
            return await self.history.extent(self.twin_id, self.stream, None)
        except NotFoundError:  # nothing stored in the stream yet
            return None

    async def _read(self, start: int) -> tuple[list[dict[str, Any]], int]:
        """The newest MAX_REPLAY rows from `start` on, and how many older ones were left out."""
        rows: deque[dict[str, Any]] = deque(maxlen=MAX_REPLAY)
        seen = 0
        after: tuple[int, int] | None = None
        while True:
            page = await self.history.samples(
                self.twin_id, self.stream, None, start, MAX_TIME, PAGE, after
            )
            rows.extend(page.rows)
            seen += len(page.rows)
            if page.next_key is None:
                return list(rows), seen - len(rows)
            after = page.next_key

    def _batch(self, rows: list[dict[str, Any]]) -> SampleBatch:
        return SampleBatch(
            twin_id=self.twin_id,
            twin="",
            stream=self.stream,
            times=[r["time"] for r in rows],
            values=[r["values"] for r in rows],
            received_ns=time.time_ns(),
            source="history",
        )

    def _report(
        self, replayed: int, skipped: int, position: int, after: int, first: int, last: int
    ) -> None:
        data = {"replayed": replayed, "skipped": skipped, "from_ns": first, "to_ns": last,
                "dropped": self.dropped}  # fmt: skip
        events: list[EventTuple] = []
        if skipped or after > position:
            why = f"{skipped} samples skipped" if skipped else "older samples skipped"
            message = f"{why}: caught up from {_ns_iso(first)}, not from {_ns_iso(position)}"
            log.warning("processor %d: %s", self.processor_id, message,
                        extra={"event": "processor_catch_up_cut"})  # fmt: skip
            events.append(("catch_up_cut", message, time.time_ns(), data))
        message = f"caught up on {replayed} samples from {_ns_iso(first)} to {_ns_iso(last)}"
        log.info("processor %d %s", self.processor_id, message,
                 extra={"event": "processor_caught_up"})  # fmt: skip
        events.append(("caught_up", message, time.time_ns(), data))
        self.on_events(events)
