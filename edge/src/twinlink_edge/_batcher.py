"""The thread-safe core of a device: samples waiting to be sealed into batches, the sealed
batches without an ack (in a `Buffer`), the bound on both, and the order batches go out in.
With `durable`, each waiting sample is also held in the buffer's file before `add` returns.

`add` may be called from any thread; everything else runs on the device's event loop."""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from typing import Any, Callable

from ._buffer import Buffer, StoredBatch
from ._protocol import (
    MAX_BATCH_SAMPLES,
    MAX_FRAME_BYTES,
    BufferFull,
    JsonObject,
    SeqCounter,
    batch_message,
    check_stream,
    encode,
)

log = logging.getLogger("twinlink_edge")

ON_FULL = ("block", "drop_oldest", "error")


class Batcher:
    def __init__(
        self,
        buffer: Buffer,
        *,
        batch_size: int,
        max_samples: int,
        on_full: str,
        notify: Callable[[bool], None],
        durable: bool = False,
    ) -> None:
        if on_full not in ON_FULL:
            raise ValueError(f"on_full is one of {', '.join(ON_FULL)}, not {on_full!r}")
        if max_samples < batch_size:
            raise ValueError("max_buffered_samples must be at least batch_size")
        if durable and not buffer.keeps_samples:
            raise ValueError(
                "durable=True writes each sample to the device's disk: give `buffer` a folder"
            )
        self.buffer = buffer
        self.durable = durable
        self.batch_size = batch_size
        self.max_samples = max_samples
        self.on_full = on_full
        self.dropped_samples = 0
        self._notify = notify  # notify(True): batches sealed or dropped; (False): first pending
        self._lock = threading.Lock()
        self._space = threading.Condition(self._lock)
        self._pending: dict[str, list[JsonObject]] = {}
        self._pending_count = 0
        self._seq = SeqCounter(buffer.last_seq)
        self._queue: deque[int] = deque(buffer.seqs())  # to send, in order
        self._streams: set[str] = set()
        self._closed = False
        self._drop_logged = 0.0
        for stream, item in buffer.held():  # added by an earlier run, never sealed
            self._pending.setdefault(stream, []).append(item)
            self._pending_count += 1

    @property
    def buffered_samples(self) -> int:
        """Samples not acknowledged yet: waiting to be sealed, or sealed and unacknowledged."""
        return self._pending_count + self.buffer.samples

    @property
    def pending_samples(self) -> int:
        return self._pending_count

    def add(self, sample: JsonObject, stream: str, *, wait: bool) -> bool:
        """Take a sample. When the buffer is full under `on_full="block"`, wait for room when
        `wait`, else return False without taking it."""
        if stream not in self._streams:
            self._streams.add(check_stream(stream))
        with self._lock:
            dropped = self._make_room(wait)
            if dropped is None:
                return False
            if self.durable:  # on disk before anything else: an error leaves nothing taken
                self.buffer.hold(stream, sample)
            pending = self._pending.setdefault(stream, [])
            pending.append(sample)
            self._pending_count += 1
            first = self._pending_count == 1
            sealed = len(pending) >= self.batch_size
            if sealed:
                self._seal(stream)
        if sealed or dropped:
            self._notify(True)
        elif first:
            self._notify(False)
        return True

    def _make_room(self, wait: bool) -> bool | None:
        """Under the lock: True when batches were dropped for room, False when there was room,
        None when there is none and the caller may not wait."""
        dropped = False
        while self.buffered_samples >= self.max_samples:
            if self._closed:
                raise RuntimeError("the device is closed")
            if self.on_full == "error":
                raise BufferFull(f"{self.buffered_samples} samples are waiting for an ack")
            if self.on_full == "drop_oldest":
                self._drop_oldest()
                dropped = True
            elif not wait:
                return None
            else:
                self._space.wait()
        if self._closed:
            raise RuntimeError("the device is closed")
        return dropped

    def _drop_oldest(self) -> None:
        if not len(self.buffer):
            self._seal_all()
        seq = self.buffer.first_seq()
        if seq is None:  # pragma: no cover - max_samples >= batch_size rules it out
            return
        self.dropped_samples += self.buffer.remove(seq) or 0
        now = time.monotonic()
        if now - self._drop_logged > 10:
            self._drop_logged = now
            log.warning(
                "buffer full (%d samples): dropped the oldest batches, %d samples so far",
                self.max_samples,
                self.dropped_samples,
            )

    def _seal(self, stream: str) -> None:
        samples = self._pending.pop(stream)
        self._pending_count -= len(samples)
        batches: list[StoredBatch] = []
        for start in range(0, len(samples), self.batch_size):  # more after a restart
            self._encode(stream, samples[start : start + self.batch_size], batches)
        # The samples held on disk for the stream go with the batches that now carry them.
        self.buffer.put_all(batches, released=stream)
        self._queue.extend(batch.seq for batch in batches)

    def _encode(self, stream: str, samples: list[JsonObject], out: list[StoredBatch]) -> None:
        seq = self._seq.next()
        payload, size = encode(batch_message(seq, stream, samples))
        if size > MAX_FRAME_BYTES and len(samples) > 1:  # too large a frame: halve it
            half = len(samples) // 2
            self._encode(stream, samples[:half], out)
            self._encode(stream, samples[half:], out)
            return
        out.append(StoredBatch(seq, stream, len(samples), payload))

    def _seal_all(self) -> None:
        for stream in list(self._pending):
            self._seal(stream)

    def seal_all(self) -> int:
        """Seal every waiting sample; returns the last sequence number given out."""
        with self._lock:
            sealed = self._pending_count > 0 and not self._closed
            if sealed:
                self._seal_all()
            last = self._seq.last
        if sealed:
            self._notify(True)
        return last

    def next_to_send(self) -> StoredBatch | None:
        """The oldest batch not sent on this connection yet."""
        with self._lock:
            while self._queue and not self._closed:
                batch = self.buffer.get(self._queue.popleft())
                if batch is not None:
                    return batch
        return None

    def rewind(self) -> None:
        """A new connection: every batch without an ack goes out again, in order."""
        with self._lock:
            if not self._closed:
                self._queue = deque(self.buffer.seqs())

    def requeue(self, seq: int) -> bool:
        """Send batch `seq` again next (the server asked for it); False when not held."""
        with self._lock:
            if self._closed or seq not in self.buffer:
                return False
            self._queue.appendleft(seq)
            return True

    def remove(self, seq: int) -> int | None:
        """Batch `seq` was answered: forget it. Returns its number of samples, None when it
        was not held (answered before, or dropped)."""
        with self._lock:
            if self._closed:
                return None
            count = self.buffer.remove(seq)
            if count is not None:
                self._space.notify_all()
        return count

    def done_through(self, seq: int) -> bool:
        """No batch up to `seq` waits for an ack."""
        with self._lock:
            first = None if self._closed else self.buffer.first_seq()
        return first is None or first > seq

    def close(self) -> None:
        """Seal what waits (a disk buffer keeps it for the next run) and close the buffer."""
        with self._lock:
            if self._closed:
                return
            self._seal_all()
            self._closed = True
            self._space.notify_all()
            self.buffer.close()

    def counts(self) -> dict[str, Any]:
        with self._lock:
            return {
                "pending_samples": self._pending_count,
                "unacked_batches": len(self.buffer),
                "unacked_samples": self.buffer.samples,
                "dropped_samples": self.dropped_samples,
            }


def check_options(
    token: str, batch_size: int, flush_interval: float, window: int, max_samples: int, on_full: str
) -> None:
    """The settings of a device, checked before anything is opened."""
    if not token:
        raise ValueError("a device token (tld_...) is required")
    if not 1 <= batch_size <= MAX_BATCH_SAMPLES:
        raise ValueError(f"batch_size is between 1 and {MAX_BATCH_SAMPLES}")
    if flush_interval < 0 or window < 1:
        raise ValueError("flush_interval must be >= 0 and window >= 1")
    if max_samples < batch_size:
        raise ValueError("max_buffered_samples must be at least batch_size")
    if on_full not in ON_FULL:
        raise ValueError(f"on_full is one of {', '.join(ON_FULL)}, not {on_full!r}")
