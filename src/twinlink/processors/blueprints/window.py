"""Moving-window aggregates: mean, RMS, min, max, peak-to-peak, standard deviation, count.

Each signal keeps the tail of its own values that a later window can still reach, so the
results do not depend on how the samples are split into batches. Sums come from running sums
over that tail (shifted by a reference value for precision); minima and maxima from a sparse
table, so a batch costs O((tail + batch) log window) whatever the window length.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
import numpy.typing as npt
from pydantic import AfterValidator, Field, model_validator

from twinlink.processors.blueprint import (
    MAX_SPAN_S,
    Batch,
    Blueprint,
    Context,
    Names,
    Params,
    distinct,
)

Array = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Function = Literal["mean", "rms", "min", "max", "p2p", "std", "count"]
SUMS = frozenset({"mean", "rms", "std"})
EXTREMES = frozenset({"min", "max", "p2p"})


def _mean() -> list[Function]:
    return ["mean"]


class WindowParams(Params):
    signals: Names = Field(min_length=1, description="The signals to aggregate.")
    functions: Annotated[list[Function], AfterValidator(distinct)] = Field(
        default_factory=_mean,
        min_length=1,
        description="Aggregates to compute: mean, rms (root mean square), min, max, p2p "
        "(peak to peak, max - min), std (population standard deviation) and count (number "
        "of values in the window). Each gives the output `{signal}.{function}`.",
    )
    window_s: float | None = Field(
        None,
        gt=0,
        le=MAX_SPAN_S,
        description="Window length in seconds: the window ending at time t holds the values "
        "with t - window_s < time <= t. Set this or window_samples.",
    )
    window_samples: int | None = Field(
        None,
        ge=1,
        le=10_000_000,
        description="Window length in samples: the window holds the signal's latest this many "
        "values. Set this or window_s.",
    )
    hop_s: float = Field(
        0.0,
        ge=0,
        le=MAX_SPAN_S,
        description="Output interval in seconds. 0: an output at every sample (rolling). "
        "Otherwise one output per interval that had samples, at its end (a multiple of hop_s "
        "since the epoch), made when the first sample after it arrives.",
    )

    @model_validator(mode="after")
    def _one_window(self) -> WindowParams:
        if (self.window_s is None) == (self.window_samples is None):
            raise ValueError("set exactly one of window_s and window_samples")
        return self


def range_extreme(x: Array, lo: Ints, hi: Ints, ufunc: np.ufunc) -> Array:
    """`ufunc`-reduction (np.minimum or np.maximum) of each x[lo:hi]; NaN where empty.

    A sparse table built one level at a time: level j holds the extreme of x[i : i + 2**j],
    and a range of length n is covered by two (overlapping) blocks of 2**floor(log2(n)).
    """
    out = np.full(lo.shape, np.nan)
    length = hi - lo
    index = np.flatnonzero(length > 0)
    if index.shape[0] == 0:
        return out
    level_of = np.log2(length[index]).astype(np.int64)
    level = x
    for j in range(int(level_of.max()) + 1):
        if j:
            half = 1 << (j - 1)
            level = ufunc(level[:-half], level[half:])
        sel = index[level_of == j]
        if sel.shape[0]:
            out[sel] = ufunc(level[lo[sel]], level[hi[sel] - (1 << j)])
    return out


def aggregate(x: Array, lo: Ints, hi: Ints, functions: list[Function]) -> dict[str, Array]:
    """Each function over each window x[lo:hi] (NaN for an empty window, count 0)."""
    count = (hi - lo).astype(np.float64)
    out: dict[str, Array] = {}
    if SUMS.intersection(functions):
        ref = x[0] if x.shape[0] else 0.0
        d = x - ref
        s1 = np.concatenate([[0.0], np.cumsum(d)])
        s2 = np.concatenate([[0.0], np.cumsum(d * d)])
        with np.errstate(divide="ignore", invalid="ignore"):
            m1 = (s1[hi] - s1[lo]) / count
            var = np.maximum((s2[hi] - s2[lo]) / count - m1 * m1, 0.0)
        var[count == 1] = 0.0
        mean = m1 + ref
        out.update(mean=mean, std=np.sqrt(var), rms=np.sqrt(var + mean * mean))
    if EXTREMES.intersection(functions):
        low = range_extreme(x, lo, hi, np.minimum)
        high = range_extreme(x, lo, hi, np.maximum)
        out.update(min=low, max=high, p2p=high - low)
    out["count"] = count
    return {f: out[f] for f in functions}


class WindowAggregate(Blueprint[WindowParams]):
    """Moving-window aggregates

    Mean, RMS, min, max, peak-to-peak, standard deviation and count of each signal over a
    moving window of time or of samples, at every sample or every `hop_s` seconds. Missing
    values are ignored; an empty window gives NaN (count 0). Outputs are `{signal}.{function}`.
    """

    name = "window"
    Params = WindowParams
    keeps_state = True

    def __init__(self, params: WindowParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._times: dict[str, Ints] = {}
        self._values: dict[str, Array] = {}
        self._last: int | None = None  # time of the latest sample
        self._pending: int | None = None  # end of the hop interval not closed yet

    def inputs(self) -> list[str]:
        return list(self.params.signals)

    def outputs(self) -> list[str]:
        return [f"{s}.{f}" for s in self.params.signals for f in self.params.functions]

    def reconfigure(self, params: WindowParams) -> bool:
        """Keeps the retained values when the signals are unchanged."""
        if params.signals != self.params.signals:
            return False
        if params.hop_s != self.params.hop_s:
            self._pending = None
            if params.hop_s > 0 and self._last is not None:
                self._pending = int(-(-self._last // hop_ns(params.hop_s)) * hop_ns(params.hop_s))
        self.params = params
        return True

    def process(self, batch: Batch) -> Batch | None:
        valid = {
            s: np.isfinite(c)
            for s in self.params.signals
            if (c := batch.columns.get(s)) is not None
        }
        rows = np.zeros(len(batch), dtype=bool)
        for ok in valid.values():
            rows |= ok
        if not rows.any():
            return None
        row_times = batch.times[rows]
        queries = row_times if self.params.hop_s == 0 else self._closed(row_times)
        out: dict[str, Array] = {}
        for s in self.params.signals:
            ok = valid.get(s, np.zeros(len(batch), dtype=bool))
            base = self._append(s, batch.times[ok], batch.columns[s][ok] if s in valid else None)
            if queries.shape[0]:
                hi = self._ends(s, queries, base + np.cumsum(ok)[rows])
                lo = self._starts(s, queries, hi)
                for f, v in aggregate(self._values[s], lo, hi, self.params.functions).items():
                    out[f"{s}.{f}"] = v
        self._last = int(row_times[-1])
        for s in self.params.signals:
            self._trim(s)
        return Batch(queries, out) if queries.shape[0] else None

    def _closed(self, row_times: Ints) -> Ints:
        """The ends of the hop intervals that these samples close (and keeps the open one)."""
        step = hop_ns(self.params.hop_s)
        ends = -(-row_times // step) * step
        if self._pending is not None:
            ends = np.concatenate([[self._pending], ends[ends >= self._pending]])
        distinct = np.unique(ends)
        self._pending = int(distinct[-1])
        return distinct[:-1]

    def _append(self, s: str, times: Ints, values: Array | None) -> int:
        """Adds the new values to the signal's tail; returns the tail's length before."""
        old_t = self._times.get(s, np.empty(0, np.int64))
        old_v = self._values.get(s, np.empty(0, np.float64))
        if values is not None and values.shape[0]:
            self._times[s] = np.concatenate([old_t, times])
            self._values[s] = np.concatenate([old_v, values])
        else:
            self._times[s], self._values[s] = old_t, old_v
        return int(old_t.shape[0])

    def _ends(self, s: str, queries: Ints, at_rows: Ints) -> Ints:
        """Index just past the last value of each window: the row itself when rolling."""
        if self.params.hop_s == 0:
            return at_rows.astype(np.int64)
        return np.searchsorted(self._times[s], queries, side="right").astype(np.int64)

    def _starts(self, s: str, queries: Ints, hi: Ints) -> Ints:
        if self.params.window_samples is not None:
            return np.maximum(hi - self.params.window_samples, 0)
        start = queries - window_ns(self.params.window_s)
        lo = np.searchsorted(self._times[s], start, side="right").astype(np.int64)
        return np.minimum(lo, hi)

    def _trim(self, s: str) -> None:
        """Drops the values no later window can reach."""
        times = self._times[s]
        if self.params.window_samples is not None:
            cut = max(times.shape[0] - self.params.window_samples, 0)
        else:
            assert self._last is not None
            limit = self._last - window_ns(self.params.window_s)
            cut = int(np.searchsorted(times, limit, side="right"))
        if cut:
            self._times[s] = times[cut:]
            self._values[s] = self._values[s][cut:]


def hop_ns(hop_s: float) -> int:
    return max(round(hop_s * 1e9), 1)


def window_ns(window_s: float | None) -> int:
    return max(round((window_s or 0.0) * 1e9), 1)
