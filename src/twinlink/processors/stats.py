"""Figures of one processor: counters, and recent step times and latencies as percentiles."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

WINDOW = 4096


@dataclass(slots=True)
class Recent:
    """The last WINDOW values of a quantity, for percentiles without unbounded memory."""

    values: np.ndarray = field(default_factory=lambda: np.zeros(WINDOW))
    count: int = 0

    def add(self, value: float) -> None:
        self.values[self.count % WINDOW] = value
        self.count += 1

    def percentiles(self, *qs: float) -> list[float | None]:
        n = min(self.count, WINDOW)
        if n == 0:
            return [None for _ in qs]
        return [float(v) for v in np.percentile(self.values[:n], qs)]


@dataclass(slots=True)
class ProcessorStats:
    samples_in: int = 0
    samples_out: int = 0
    batches: int = 0
    dropped: int = 0  # input samples not processed: the worker was down or too far behind
    restarts: int = 0
    crashes: int = 0
    rss_bytes: int = 0
    step_s: Recent = field(default_factory=Recent)  # blueprint time per input sample
    latency_s: Recent = field(default_factory=Recent)  # input on the bus -> output on the bus

    def timed(self, timings: list[tuple[int, int]]) -> None:
        for busy_ns, n in timings:
            if n:
                self.step_s.add(busy_ns / n / 1e9)

    def view(self) -> dict[str, Any]:
        step50, step99 = self.step_s.percentiles(50, 99)
        lat50, lat99 = self.latency_s.percentiles(50, 99)
        return {
            "samples_in": self.samples_in,
            "samples_out": self.samples_out,
            "batches": self.batches,
            "dropped": self.dropped,
            "restarts": self.restarts,
            "crashes": self.crashes,
            "rss_bytes": self.rss_bytes,
            "step_time_s": {"p50": step50, "p99": step99},
            "added_latency_s": {"p50": lat50, "p99": lat99},
        }
