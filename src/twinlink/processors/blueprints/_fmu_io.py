"""Getting samples into and out of an FMU: input conditioning and output reading."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..blueprint import Context
from ..fmuinfo import FLOAT_TYPES, FmuVariable
from ..fmurules import INT_RANGES
from ._fmu_fmi import WARNING, FmiApi, FmuLog, fmi_failure

NS = 1_000_000_000


def input_range(var: FmuVariable, fmi3: bool) -> tuple[float, float]:
    """The values an input can take: its declared min/max, within its type's range (an
    integer outside it would wrap around in the FMU; an enumeration's declared items)."""
    low = var.min if var.min is not None else -math.inf
    high = var.max if var.max is not None else math.inf
    if var.type == "Boolean":
        return max(low, 0.0), min(high, 1.0)
    if var.type == "Enumeration":
        if var.items:
            values = [v for _, v in var.items]
            return max(low, min(values)), min(high, max(values))
        type_low, type_high = INT_RANGES["Int64" if fmi3 else "Integer"]
        return max(low, type_low), min(high, type_high)
    if var.type in INT_RANGES:
        type_low, type_high = INT_RANGES[var.type]
        return max(low, type_low), min(high, type_high)
    return low, high


class InputSetter:
    """Sets a row of the (samples, inputs) float64 array into the FMU's inputs.

    Real/Float64 inputs alone (the usual case) are set straight from the row's address, as
    before. Inputs of other types are converted a batch at a time (`bind`, vectorized:
    integers rounded, booleans nonzero) into one array per type, and a row is set with one
    FMI call per type, so no value is converted per sample."""

    def __init__(self, api: FmiApi, inputs: list[FmuVariable]) -> None:
        self.api = api
        types = sorted({v.type for v in inputs}, key=lambda t: t != api.REAL)
        self.name = api.function("Set", types[0] if types else api.REAL)
        self.direct = not types or types == [api.REAL]
        self._groups = []
        for type_ in types:
            columns = [j for j, v in enumerate(inputs) if v.type == type_]
            vrs = [inputs[j].value_reference for j in columns]
            dtype = np.dtype(api.DTYPES[type_])
            self._groups.append((api.accessor("Set", type_, vrs), columns, dtype, type_))
        self.call = self._groups[0][0] if self.direct and types else self._set
        self._base, self._stride = 0, 1
        self._bound: list[tuple[Callable[[int], int], int, int, np.ndarray, str]] = []

    def bind(self, u: np.ndarray) -> None:
        """Convert the batch `u` (C-contiguous) the next calls take rows of."""
        if self.direct:
            return
        self._base, self._stride = u.ctypes.data, max(u.strides[0], 1)
        self._bound = []
        for set_, columns, dtype, type_ in self._groups:
            values = u[:, columns]
            if type_ == "Boolean":
                typed = np.ascontiguousarray(values != 0, dtype=dtype)
            elif type_ in FLOAT_TYPES:
                typed = np.ascontiguousarray(values, dtype=dtype)
            else:  # in range (InputGuard), so the cast is exact
                typed = np.ascontiguousarray(np.rint(values), dtype=dtype)
            self._bound.append((set_, typed.ctypes.data, typed.strides[0], typed, type_))

    def _set(self, values_at: int) -> int:
        k = (values_at - self._base) // self._stride
        worst = 0
        for set_, base, stride, _, type_ in self._bound:
            status = set_(base + k * stride)
            if status > worst:  # the function named if it fails
                worst, self.name = status, self.api.function("Set", type_)
        return worst


class InputGuard:
    """Turns input columns into the rows the FMU gets.

    Values outside an input's declared min/max are clamped (mode "clamp") or make the whole
    sample be skipped ("reject"); both are counted per input and reported as an event at most
    once per second of sample time per input. NaN (no value) holds the previous value.
    """

    def __init__(
        self,
        inputs: list[FmuVariable],
        held: list[float],
        mode: str,
        ctx: Context,
        fmi3: bool = False,
    ) -> None:
        self.names = [v.name for v in inputs]
        ranges = [input_range(v, fmi3) for v in inputs]
        self.low = [low for low, _ in ranges]
        self.high = [high for _, high in ranges]
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
