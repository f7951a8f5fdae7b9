"""One client subscription to one stream of one twin: which signals, how often, what is sent.

The filter and the decimation run in the connection's writer task, never in the bus handler,
so a subscription's cost falls on its own connection and not on ingest.

Decimation (`max_rate`, samples per second) goes by sample time: a sample is kept when at
least 1/max_rate seconds passed since the last sample this subscription kept, or when its time
is earlier than that one (a device whose clock went back starts the count again). Samples are
filtered first, so a sample without any of the subscribed signals neither counts nor is sent.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import orjson

from twinlink.domain.samples import SampleBatch, Value


@dataclass(slots=True, eq=False)
class Subscription:
    id: str
    twin_id: int
    twin: str
    stream: str
    signals: frozenset[str] | None = None
    max_rate: float | None = None
    # False until the `subscribed` answer is queued: samples wait behind it, never overtake it.
    started: bool = False
    # False once unsubscribed: what is still queued for it is discarded, not sent.
    active: bool = True
    _interval_ns: int = field(init=False, default=0)
    _last_kept_ns: int | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        if self.max_rate is not None:
            self._interval_ns = round(1e9 / self.max_rate)

    @property
    def key(self) -> tuple[int, str]:
        return self.twin_id, self.stream

    def select(self, batch: SampleBatch) -> list[dict[str, Any]]:
        """The samples of `batch` this subscription sends: filtered, then decimated."""
        out: list[dict[str, Any]] = []
        signals = self.signals
        decimate = self.max_rate is not None
        for time_ns, values in zip(batch.times, batch.values, strict=True):
            kept: dict[str, Value] = values
            if signals is not None:
                kept = {name: v for name, v in values.items() if name in signals}
                if not kept:
                    continue
            if decimate and not self._keep(time_ns):
                continue
            out.append({"time": time_ns, "values": kept})
        return out

    def _keep(self, time_ns: int) -> bool:
        last = self._last_kept_ns
        if last is None or time_ns - last >= self._interval_ns or time_ns < last:
            self._last_kept_ns = time_ns
            return True
        return False

    def message(self, batch: SampleBatch, sent_ns: int) -> bytes | None:
        """One `samples` message for the whole batch, or None when nothing of it is kept."""
        samples = self.select(batch)
        if not samples:
            return None
        return orjson.dumps(
            {
                "type": "samples",
                "sub": self.id,
                "twin": self.twin,
                "stream": self.stream,
                "received": batch.received_ns,
                "sent": sent_ns,
                "samples": samples,
            }
        )
