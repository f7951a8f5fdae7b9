"""Co-simulation: one doStep per advance. Also the base class of both ways to run an FMU."""

from __future__ import annotations

from typing import Any

from ..fmuinfo import FmuVariable, Scalar
from ._fmu_fmi import WARNING, FmiApi, FmuLog, fmi_failure, set_values


class Engine:
    """Runs an initialized FMU instance forward in time (FMU time 0 = the first sample)."""

    def __init__(self, fmu: Any, api: FmiApi, log: FmuLog, inputs: list[FmuVariable]) -> None:
        self.fmu = fmu
        self.api = api
        self.log = log
        self.time = 0.0
        self.prefix = api.prefix
        self._set = api.accessor("Set", api.REAL, [v.value_reference for v in inputs])

    def begin(self) -> None:
        """Called once after exitInitializationMode."""

    def set_inputs(self, values_at: int) -> None:
        """Set all inputs from the doubles at address `values_at`."""
        status = self._set(values_at)
        if status > WARNING:
            name = self.api.function("Set", self.api.REAL)
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
        status = self._do_step(self.time, t_end - self.time)
        if status > WARNING:
            raise fmi_failure(f"{self.prefix}DoStep", status, self.log, f" at t = {self.time:g} s")
        self.time = t_end
