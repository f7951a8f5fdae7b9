"""Stepping a co-simulation on live samples (the `cosim` blueprint's hot loop): time 0 at the
first sample, the grid up to each batch's last sample, the latest inputs held.

Python work is per macro step (as the Session's own is), not per sample and signal: the
samples that apply to a step are found by bisection on the batch's times, and inputs are
set again only when they changed.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.fmuinfo import FLOAT_TYPES

from .model import Port, System
from .session import Session


class Feed:
    """Steps a Session on live samples: the held inputs, the grid, time 0 at the first
    sample."""

    def __init__(
        self, session: Session, system: System, ports: list[Port], columns: list[int]
    ) -> None:
        self.session = session
        self.ports = ports
        self.columns = columns
        self.start = system.start_time
        self.end = system.end_time
        algorithm = system.algorithm
        self.fixed = algorithm.kind == "fixed-step"
        self.h = algorithm.size
        self.tol = 1e-9 * (algorithm.min_size or algorithm.size)
        self.t0_ns: int | None = None
        self.held = [math.nan] * len(ports)  # the inputs after the last batch (NaN: none yet)
        self.sent: tuple[float, ...] | None = None  # the values last set
        self.ended = ""  # why the co-simulation ended: the processor then finishes

    def run(
        self, times: npt.NDArray[np.int64], u: npt.NDArray[np.float64]
    ) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        """Step up to the last of `times` (sorted), `u` the inputs held at each sample (NaN:
        no value yet); the times (ns) and rows of the communication points reached."""
        values = u.tolist()
        rows: list[npt.NDArray[np.float64]] = []
        if self.t0_ns is None:
            self.t0_ns = int(times[0])
            r = ((times - self.t0_ns) * 1e-9).tolist()
            self._set(values[bisect.bisect_right(r, self.tol) - 1])
            rows.append(self.session.initialize())
        else:
            r = ((times - self.t0_ns) * 1e-9).tolist()
        before = self.held
        while not self.ended and self._due(r[-1]):
            s = self.session.time - self.start
            if self.fixed:  # the samples up to this step's end, as the FMU blueprint's grid
                k = bisect.bisect_left(r, s + self.h - self.tol) - 1
            else:  # a step of unknown length: the samples up to its start
                k = bisect.bisect_right(r, s + self.tol) - 1
            self._set(values[k] if k >= 0 else before)
            row = self.session.step()
            if row is None:
                self._end()
                break
            if not self.session.time > s + self.start:  # it would never catch up
                raise BlueprintError(f"the co-simulation did not advance from t = {s:g} s")
            rows.append(row)
            self._end_if_done()
        self.held = values[-1]
        if not rows:
            return np.empty(0, np.int64), np.empty((0, len(self.session.columns)))
        table = np.vstack(rows)
        out = self.t0_ns + np.rint((table[:, 0] - self.start) * 1e9).astype(np.int64)
        return out, table

    def _due(self, last: float) -> bool:
        """Whether the next step ends no later than the last sample (var-step: starts
        before it, its end unknown until taken)."""
        s = self.session.time - self.start
        return s + self.h <= last + self.tol if self.fixed else s < last - self.tol

    def _set(self, values: Sequence[float]) -> None:
        key = tuple(values)
        if key == self.sent:
            return
        self.session.set_inputs(
            {p: v for p, v in zip(self.ports, values, strict=True) if not math.isnan(v)}
        )
        self.sent = key

    def _end_if_done(self) -> None:
        if self.session.ended or (
            self.end is not None and self.session.time >= self.end - self.tol
        ):
            self._end()

    def _end(self) -> None:
        if self.session.ended:
            self.ended = f"the co-simulation ended: {self.session.ended}"
        else:
            self.ended = f"the co-simulation reached its end time t = {self.end:g} s"


def typed(u: npt.NDArray[np.float64], types: Sequence[str]) -> None:
    """Round the values of integer and Enumeration inputs in place, and make a Boolean's
    nonzero values 1 (as the FMU blueprint sets them); NaN (no value yet) stays."""
    for j, kind in enumerate(types):
        column = u[:, j]
        if kind == "Boolean":
            column[(column != 0) & ~np.isnan(column)] = 1.0
        elif kind not in FLOAT_TYPES:
            np.rint(column, out=column)
