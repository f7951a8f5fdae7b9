"""Co-simulation: one doStep per advance. Also the base class of both ways to run an FMU."""

from __future__ import annotations

from typing import Any

from ..fmuinfo import FmuVariable, Scalar
from ._fmu_fmi import (
    DISCARD,
    EARLY_RETURN,
    TERMINATE,
    WARNING,
    FmiApi,
    FmuLog,
    Terminated,
    fmi_failure,
    set_values,
)
from ._fmu_io import InputSetter

# A step the FMU discards without terminating is retried from where it got, in halves, at
# most this many times before the FMU is taken to be stuck (FMI 2.0.4 section 4.2.2: after
# fmi2Discard the master may go on with a smaller step).
DISCARD_RETRIES = 20


class Engine:
    """Runs an initialized FMU instance forward in time (FMU time 0 = the first sample)."""

    def __init__(self, fmu: Any, api: FmiApi, log: FmuLog, inputs: list[FmuVariable]) -> None:
        self.fmu = fmu
        self.api = api
        self.log = log
        self.time = 0.0
        self.prefix = api.prefix
        self.setter = InputSetter(api, inputs)  # inputs of other types: _fmu_io.py
        self._set = self.setter.call

    def begin(self) -> None:
        """Called once after exitInitializationMode."""

    def set_inputs(self, values_at: int) -> None:
        """Set all inputs from the doubles at address `values_at`."""
        status = self._set(values_at)
        if status > WARNING:
            name = self.setter.name
            raise fmi_failure(name, status, self.log, f" at t = {self.time:g} s")

    def advance(self, t_end: float) -> None:
        raise NotImplementedError

    def retune(self, values: list[tuple[FmuVariable, Scalar]]) -> None:
        """Set tunable parameters while running."""
        set_values(self.fmu, self.api.fmi3, values, self.log)

    def close(self) -> None:
        """Release what the engine holds besides the FMU instance."""


class CoSimulation(Engine):
    def __init__(self, fmu: Any, api: FmiApi, log: FmuLog, inputs: list[FmuVariable]) -> None:
        super().__init__(fmu, api, log, inputs)
        self._do_step = api.do_step

    def advance(self, t_end: float) -> None:
        """Step to `t_end`; Terminated when the FMU ends the simulation on the way (its
        outputs are then those at the time it ended)."""
        status = self._do_step(self.time, t_end - self.time)
        if status <= WARNING:
            self.time = t_end
            return
        self._unfinished(status, t_end)

    def _unfinished(self, status: int, t_end: float) -> None:
        """The step did not reach `t_end`: the FMU terminated, returned early (FMI 3) or
        discarded it (FMI 2: the step was too large). Goes on from its last successful time,
        with half the step when it got nowhere."""
        h = t_end - self.time
        for _ in range(DISCARD_RETRIES):
            if status > WARNING and status not in (DISCARD, TERMINATE, EARLY_RETURN):
                when = f" at t = {self.time:g} s"
                raise fmi_failure(f"{self.prefix}DoStep", status, self.log, when)
            if status <= WARNING:  # this step was done
                self.time = t_end if h >= t_end - self.time else self.time + h
            else:
                terminated, reached = self.api.discarded(self.time)
                if reached > self.time:
                    self.time = min(reached, t_end)
                elif status == DISCARD:
                    h /= 2
                if terminated or status == TERMINATE:
                    raise Terminated(self.time)
            if self.time >= t_end:
                return
            h = min(h, t_end - self.time)
            status = self._do_step(self.time, h)
        message = f"{self.prefix}DoStep keeps discarding the step to t = {t_end:g} s"
        raise fmi_failure(message, DISCARD, self.log, f" (stuck at t = {self.time:g} s)")
