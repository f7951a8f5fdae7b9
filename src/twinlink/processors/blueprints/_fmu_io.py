"""Getting samples into and out of an FMU: input conditioning and output reading."""

from __future__ import annotations

import math

import numpy as np

from ..blueprint import Context
from ..fmuinfo import FmuVariable
from ._fmu_fmi import WARNING, FmiApi, FmuLog, fmi_failure

NS = 1_000_000_000


class InputGuard:
    """Turns input columns into the rows the FMU gets.

    Values outside an input's declared min/max are clamped (mode "clamp") or make the whole
    sample be skipped ("reject"); both are counted per input and reported as an event at most
    once per second of sample time per input. NaN (no value) holds the previous value.
    """

    def __init__(
        self, inputs: list[FmuVariable], held: list[float], mode: str, ctx: Context
    ) -> None:
        self.names = [v.name for v in inputs]
        self.low = [v.min if v.min is not None else -math.inf for v in inputs]
        self.high = [v.max if v.max is not None else math.inf for v in inputs]
        self.held = np.array(held, dtype=np.float64)
        self.mode = mode
        self.ctx = ctx
        self.counts = [0] * len(inputs)
        self.skipped = 0
        self._last_event: list[int | None] = [None] * len(inputs)

    def condition(
        self, times: np.ndarray, columns: list[np.ndarray | None]
    ) -> tuple[np.ndarray, np.ndarray]:
        """The sample times kept and a C-contiguous (samples, inputs) array of values."""
        u = np.empty((len(times), len(self.names)), dtype=np.float64)
        for j, column in enumerate(columns):
            u[:, j] = np.nan if column is None else column
        skip = np.zeros(len(times), dtype=bool)
        for j in range(len(self.names)):
            lo, hi = self.low[j], self.high[j]
            if lo == -math.inf and hi == math.inf:
                continue
            column = u[:, j]
            bad = (column < lo) | (column > hi)
            if not bad.any():
                continue
            where = np.flatnonzero(bad)
            self._report(j, times[where], column[where])
            if self.mode == "clamp":
                np.clip(column, lo, hi, out=column)
            else:
                skip |= bad
        if skip.any():
            self.skipped += int(skip.sum())
            times, u = times[~skip], u[~skip]
        self._hold(u)
        return times, np.ascontiguousarray(u)

    def _hold(self, u: np.ndarray) -> None:
        n = u.shape[0]
        if n == 0:
            return
        for j in range(u.shape[1]):
            column = u[:, j]
            missing = np.isnan(column)
            if missing.any():
                last = np.where(missing, 0, np.arange(1, n + 1))
                np.maximum.accumulate(last, out=last)
                column[:] = np.where(last > 0, column[last - 1], self.held[j])
        self.held = u[-1].copy()

    def _report(self, j: int, times: np.ndarray, values: np.ndarray) -> None:
        """Count the bad values of input j; an event at most once per second of sample time."""
        kind = "input_clamped" if self.mode == "clamp" else "input_rejected"
        before = self.counts[j]
        self.counts[j] += len(times)
        last = self._last_event[j]
        pos = 0
        while pos < len(times):
            if last is not None and times[pos] < last + NS:
                pos = max(pos + 1, int(np.searchsorted(times, last + NS)))
                continue
            last = int(times[pos])
            count = before + pos + 1
            lo, hi = self.low[j], self.high[j]
            self.ctx.event(
                kind,
                f"{self.names[j]} = {values[pos]:g} is outside [{lo:g}, {hi:g}]; "
                f"{count} value(s) {'clamped' if self.mode == 'clamp' else 'rejected'} so far",
                last,
                input=self.names[j],
                value=float(values[pos]),
                count=count,
                min=lo if math.isfinite(lo) else None,
                max=hi if math.isfinite(hi) else None,
            )
        self._last_event[j] = last


class OutputReader:
    """Reads the chosen outputs after each step, one FMI call per type, straight into row k of
    a preallocated array of that type; `columns` converts them to float64 columns."""

    def __init__(self, api: FmiApi, outputs: list[FmuVariable], log: FmuLog) -> None:
        self.names = [v.name for v in outputs]
        self.log = log
        self._groups = []
        for type_ in sorted({v.type for v in outputs}, key=lambda t: t != api.REAL):
            group = [v for v in outputs if v.type == type_]
            get = api.accessor("Get", type_, [v.value_reference for v in group])
            dtype = np.dtype(api.DTYPES[type_])
            self._groups.append((get, api.function("Get", type_), dtype, [v.name for v in group]))
        self.target(0)

    def target(self, rows: int) -> None:
        """Make room for `rows` output samples; `read(k)` fills row k."""
        self._arrays = [np.empty((rows, len(g[3])), dtype=g[2]) for g in self._groups]
        self._calls = [
            (g[0], g[1], a.ctypes.data, a.strides[0])
            for g, a in zip(self._groups, self._arrays, strict=True)
        ]

    def read(self, k: int) -> None:
        for get, name, base, stride in self._calls:
            status = get(base + k * stride)
            if status > WARNING:
                raise fmi_failure(name, status, self.log)

    def columns(self, rows: int | None = None) -> dict[str, np.ndarray]:
        """The first `rows` (default all) output samples, one float64 array per output."""
        out = {}
        for group, array in zip(self._groups, self._arrays, strict=True):
            for j, name in enumerate(group[3]):
                out[name] = array[:rows, j].astype(np.float64)
        return {name: out[name] for name in self.names}
