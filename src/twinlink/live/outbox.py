"""One live connection's outgoing queue: bounded, oldest dropped first, drops reported.

Two lanes. Answers to the client's own messages (`subscribed`, `error`, `pong`...) wait in
the control lane; it is bounded by back-pressure instead of drops: the connection stops reading
the client's messages while `CONTROL_LIMIT` answers are unsent. Sample batches wait in the
data lane, at most `capacity` batches (and `MAX_QUEUED_SAMPLES` samples): when it is full the
oldest batch is dropped and counted per subscription. The writer sends control answers first,
then one `dropped` message per subscription that lost data, then batches in arrival order.

`put_batch` is what the bus handler calls: it only appends a reference to the batch, so
ingest pays the same small price whatever the clients do. Filtering, decimation and JSON
encoding happen in `take`, in the connection's writer task.
"""

from __future__ import annotations

import asyncio
import time
from collections import deque
from collections.abc import Callable

from twinlink.domain.samples import SampleBatch
from twinlink.live import protocol
from twinlink.live.subscription import Subscription

CONTROL_LIMIT = 64
MAX_QUEUED_SAMPLES = 200_000


class Outbox:
    def __init__(
        self,
        capacity: int,
        max_samples: int = MAX_QUEUED_SAMPLES,
        clock: Callable[[], int] = time.time_ns,
    ) -> None:
        self.capacity = capacity
        self.max_samples = max_samples
        self._clock = clock
        self._batches: deque[tuple[Subscription, SampleBatch]] = deque()
        self._queued_samples = 0
        self._control: deque[bytes] = deque()
        self._dropped: dict[str, list[int]] = {}  # subscription id -> [messages, samples]
        self._ready = asyncio.Event()
        self._control_room = asyncio.Event()
        self._control_room.set()
        self.dropped_batches = 0  # in the life of the connection, for logs and tests

    def __len__(self) -> int:
        return len(self._batches) + len(self._control)

    def put_batch(self, sub: Subscription, batch: SampleBatch) -> None:
        """Queue `batch` for `sub`, dropping the oldest batches when the lane is full."""
        self._batches.append((sub, batch))
        self._queued_samples += len(batch)
        while len(self._batches) > 1 and (
            len(self._batches) > self.capacity or self._queued_samples > self.max_samples
        ):
            self._drop_oldest()
        self._ready.set()

    def _drop_oldest(self) -> None:
        sub, batch = self._batches.popleft()
        self._queued_samples -= len(batch)
        if not sub.active:
            return  # already unsubscribed: nothing the client still wants was lost
        counts = self._dropped.setdefault(sub.id, [0, 0])
        counts[0] += 1
        counts[1] += len(batch)
        self.dropped_batches += 1

    def put_control(self, message: dict[str, object]) -> None:
        self._control.append(protocol.encode(message))
        if len(self._control) >= CONTROL_LIMIT:
            self._control_room.clear()
        self._ready.set()

    async def control_room(self) -> None:
        """Wait until the client has read enough answers to be sent more."""
        await self._control_room.wait()

    def forget(self, sub: Subscription) -> None:
        """`sub` ended: unsent drop counts of it are no longer news to anyone."""
        sub.active = False
        self._dropped.pop(sub.id, None)

    def take(self) -> bytes | None:
        """The next message to write, or None when there is nothing to write yet. A samples
        message is stamped `sent` here, as it leaves the queue for the socket."""
        if self._control:
            message = self._control.popleft()
            if len(self._control) < CONTROL_LIMIT:
                self._control_room.set()
            return message
        if self._dropped:
            sub_id = next(iter(self._dropped))
            messages, samples = self._dropped.pop(sub_id)
            return protocol.encode(protocol.dropped(sub_id, messages, samples))
        while self._batches:
            sub, batch = self._batches[0]
            if sub.active and not sub.started:
                return None  # its `subscribed` answer is on the way; put_control wakes us
            self._batches.popleft()
            self._queued_samples -= len(batch)
            if sub.active:
                rendered = sub.message(batch, self._clock())
                if rendered is not None:
                    return rendered
        return None

    async def next_message(self) -> bytes:
        while True:
            message = self.take()
            if message is not None:
                return message
            self._ready.clear()
            await self._ready.wait()
