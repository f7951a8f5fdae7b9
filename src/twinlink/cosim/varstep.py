"""The variable-step master: each macro step's size follows how fast the exchanged values
change, between the algorithm's `min_size` and `max_size`, starting at its `size`.

Between communication points every input is held at the value it had at the step's start, so
the coupling's error over a step grows with how far the connected outputs move from a
straight line through it. The error estimate is that distance: after a step, each connected
output is compared with its linear extrapolation from the two communication points before,
weighted by a tolerance relative to the largest magnitude that output has had so far (at
least a thousandth of the largest of all of them):

    err = max_i |y_i(t + h) - extrapolated_i| / (tolerance * scale_i)

The first step has nothing to extrapolate from: it is taken at `size` (Maestro's
`initsize`) as it is, and so is the step after one kept over tolerance (a jump:
extrapolating across it would predict it again). Outputs with direct feedthrough are left
out when others exist (Session picks the outputs to watch): read after a step they still
reflect inputs held from its start, a lag that changes with the step size, so an estimate
following them rejects steps no size fixes.

A step with err <= 1 is accepted and the next one grows by 0.9 err^(-1/2) (at most twice,
up to max_size: the extrapolation's error is of order h^2). A step with err > 1 is rejected
when every instance can roll back (FMI 2 canGetAndSetFMUstate, FMI 3 getFMUState): every
instance's state saved before the step is restored, and the step is retried smaller, never
below min_size (a step at min_size is accepted whatever its error, and counted). When some
instance cannot roll back, the master still adapts its step the same way, but never rejects
one: a step over tolerance is kept and only the next one is smaller (Session.warnings says
so).

An FMI 3 early return or an fmi2Discard ends a step short for one instance while the others
reached its end: with rollback, every instance is restored and the step retried up to the
time that instance reached (halved if it got nowhere); without, the run fails naming it.

Maestro's var-step constraints (constraints.py) act on top of the estimate: each bounds the
next step before it is taken (a step so cut does not shrink the next; only a sampling point,
like the end time, may cut it below min_size), and may have a step redone shorter (a
rejection as above, counted in `rejected`; without rollback it is kept and counted in
`forced`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from .constraints import Constraints
from .master import Master
from .model import Algorithm
from .slaves import Buffer, CosimRunError

TOLERANCE = 1e-3  # relative, per connected output; see the module docstring
_GROW, _SHRINK, _SAFETY = 2.0, 0.2, 0.9
_RETRIES = 60  # attempts at one step before the master gives up (min_size stops it sooner)
_SLIVER = 0.01  # a last step this much (of h) short of the end is stretched to it

_log = logging.getLogger("twinlink.cosim")


class VarStep:
    """Takes accepted steps over a Master's slaves; counts them, the rejected ones, and
    those accepted over tolerance at min_size."""

    def __init__(
        self,
        master: Master,
        algorithm: Algorithm,
        watch: Sequence[tuple[Buffer, int]],
        tolerance: float = TOLERANCE,
        constraints: Constraints | None = None,
    ) -> None:
        self.master = master
        self.h = algorithm.size
        self.min_size = algorithm.min_size or algorithm.size
        self.max_size = algorithm.max_size or algorithm.size
        self.tolerance = tolerance
        self.constraints = constraints or Constraints([], [])
        self.rollback = all(s.can_rollback for s in master.slaves)
        self.rejected = 0  # steps rolled back and retried smaller for their error
        self.shortened = 0  # steps retried to where an instance returned early
        self.forced = 0  # steps accepted over tolerance (at min_size, or without rollback)
        self._watch = _grouped(watch)
        self._last: npt.NDArray[np.float64] | None = None  # connected outputs at t
        self._before: npt.NDArray[np.float64] | None = None  # ... at the point before
        self._h_before = 0.0
        self._scale = np.zeros(0)

    def start(self, t: float = 0.0) -> None:
        """After initialization: the connected outputs (and the constraints' ports) at the
        start time t."""
        self._last = self._outputs()
        self._scale = np.abs(self._last)
        self.constraints.start(t)

    def step(self, t: float, end: float | None) -> float:
        """One accepted step from t (not past `end`); the time reached. FmuTerminated is kept
        in master.terminated, as for fixed steps."""
        master = self.master
        h = self.h
        for _ in range(_RETRIES):
            # the last step reaches the end exactly, and leaves no sliver before it
            if end is not None and t + h * (1 + _SLIVER) >= end:
                h = end - t
            target = end if end is not None and h == end - t else t + h
            bound = self.constraints.bound(t, target)
            cut = bound < target  # by a constraint: a sampling point, a crossing ahead...
            if cut:
                target, h = bound, bound - t
            states = [s.save_state() for s in master.slaves] if self.rollback else []
            try:
                reached = master.step(t, h)
                if master.terminated is not None:
                    return reached  # the step that ended the run is kept as it is
                if reached < t + h - 4 * math.ulp(t + h):
                    h = self._cut_short(t, h, reached, states)
                    continue
                err, y = self._error(h)
                shorter = self.constraints.retry(t, h)  # a constraint's shorter step
                if (err > 1.0 or shorter is not None) and self.rollback and h > self.min_size:
                    self._restore(states)
                    self.rejected += 1
                    if err > 1.0:
                        h = h * max(_SHRINK, min(_SAFETY, _SAFETY / err**0.5))
                    h = max(self.min_size, min(h, shorter if shorter is not None else h))
                    continue
            finally:
                self._free(states)
            if err > 1.0 or shorter is not None:
                self.forced += 1
            self._accept(y, h, err, cut)
            self.constraints.accept(target, h)
            return target
        raise CosimRunError(
            f"the var-step master found no acceptable step from t = {t:g} s in {_RETRIES} "
            f"attempts (the last of {h:g} s)"
        )

    def _cut_short(self, t: float, h: float, reached: float, states: list[object]) -> float:
        """An instance ended the step at `reached` < t + h: the step size to retry with."""
        if not self.rollback:
            who = self.master.short.label if self.master.short is not None else "an instance"
            raise CosimRunError(
                f"{who} ended the step from t = {t:g} s early, at t = {reached:g} s (an FMI 3 "
                "early return or an fmi2Discard), and not every instance can restore its "
                "state (canGetAndSetFMUstate) to redo the step to that time"
            )
        self._restore(states)
        self.shortened += 1
        return reached - t if reached > t else h / 2

    def _free(self, states: list[object]) -> None:
        """Free the saved states; never raises (it runs while an error may be on its way)."""
        for slave, state in zip(self.master.slaves, states, strict=False):
            try:
                slave.free_state(state)
            except Exception as err:  # the instance is freed with its states when closed
                _log.warning("%s: %s", slave.label, err)

    def _restore(self, states: list[object]) -> None:
        for slave, state in zip(self.master.slaves, states, strict=True):
            slave.restore_state(state)
        self.master.read()  # the output buffers back at the step's start

    def _error(self, h: float) -> tuple[float, npt.NDArray[np.float64]]:
        y = self._outputs()
        last = self._last
        assert last is not None  # start() ran
        if not len(y):
            return 0.0, y  # no connected output: the FMUs' own solvers set the accuracy
        if self._before is None:
            return -1.0, y  # nothing to extrapolate from yet: accepted as it is, h kept
        predicted = last + (last - self._before) * (h / self._h_before)
        scale = np.maximum(np.maximum(self._scale, np.abs(y)), 1e-3 * float(self._scale.max()))
        scale = np.maximum(scale, 1e-300)
        return float(np.max(np.abs(y - predicted) / (self.tolerance * scale))), y

    def _accept(self, y: npt.NDArray[np.float64], h: float, err: float, cut: bool) -> None:
        # after a step kept over tolerance (a jump), extrapolating across it would predict
        # the jump again: the extrapolation starts afresh from its end
        self._before = self._last if err <= 1.0 else None
        self._last, self._h_before = y, h
        if len(y):
            np.maximum(self._scale, np.abs(y), out=self._scale)
        if err < 0.0:  # not estimated
            return
        grow = _GROW if err == 0.0 else min(_GROW, max(_SHRINK, _SAFETY / err**0.5))
        if cut:  # cut short by a constraint: its error says nothing of a longer step's
            self.h = min(self.max_size, max(self.min_size, self.h * min(grow, 1.0)))
        elif h >= self.h or grow < 1.0:  # a step cut to reach the end does not shrink h
            self.h = min(self.max_size, max(self.min_size, h * grow))

    def _outputs(self) -> npt.NDArray[np.float64]:
        if not self._watch:
            return np.zeros(0)
        return np.concatenate([buffer[ix].astype(np.float64) for buffer, ix in self._watch])


def _grouped(ports: Sequence[tuple[Buffer, int]]) -> list[tuple[Buffer, npt.NDArray[np.intp]]]:
    """The watched outputs, each once, grouped by buffer (one numpy take per buffer)."""
    groups: dict[int, tuple[Buffer, list[int]]] = {}
    for buffer, index in ports:
        entry = groups.setdefault(id(buffer), (buffer, []))
        if index not in entry[1]:
            entry[1].append(index)
    return [(buffer, np.array(ix, dtype=np.intp)) for buffer, ix in groups.values()]
