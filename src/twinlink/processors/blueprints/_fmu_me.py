"""Model exchange: FMPy's own solvers (CVode, forward Euler), driven as `simulate_fmu` does.

Between two sample times the inputs are constant (set before the interval); a change of
inputs restarts the solver, as FMPy does at input events. Time events (nextEventTime), state
events (roots of the event indicators, found by the solver) and step events
(completedIntegratorStep) each run an event iteration, after which the solver is reset.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fmpy.simulation import ForwardEuler  # type: ignore[import-untyped]

from ..blueprint import BlueprintError
from ..fmuinfo import FmuInfo, FmuVariable, Scalar
from ._fmu_cs import Engine
from ._fmu_fmi import TERMINATE, WARNING, FmiApi, FmuLog, fmi_failure, set_values

MAX_EVENT_ITERATIONS = 1000


def _or_terminate(status: int, terminate: bool) -> int:
    return TERMINATE if terminate and status <= WARNING else status


class _NoInput:
    """FMPy's solvers re-apply interpolated inputs; ours are constant over an interval."""

    def apply(self, time: float, *args: Any, **kwargs: Any) -> None:
        pass


class _SolverCalls:
    """The FMU functions FMPy's solvers call. The solver calls them from C, where an exception
    cannot go: a failing status is kept and raised once the solver returns."""

    def __init__(self, api: FmiApi) -> None:
        self.api = api
        self.failure: tuple[str, int] | None = None

    def _keep(self, name: str, status: int) -> None:
        if status > WARNING and self.failure is None:
            self.failure = (name, status)

    def set_time(self, t: float) -> None:
        self._keep("SetTime", self.api.set_time(t))

    def get_x(self, x: Any, n: int) -> None:
        self._keep("GetContinuousStates", self.api.get_x(x, n))

    def set_x(self, x: Any, n: int) -> None:
        self._keep("SetContinuousStates", self.api.set_x(x, n))

    def get_dx(self, dx: Any, n: int) -> None:
        self._keep("GetDerivatives", self.api.get_dx(dx, n))

    def get_z(self, z: Any, n: int) -> None:
        self._keep("GetEventIndicators", self.api.get_z(z, n))

    def get_nominals(self, x: Any, n: int) -> None:
        self._keep("GetNominalsOfContinuousStates", self.api.get_nominals(x, n))


class ModelExchange(Engine):
    def __init__(
        self,
        fmu: Any,
        api: FmiApi,
        log: FmuLog,
        inputs: list[FmuVariable],
        info: FmuInfo,
        solver: str,
        step: float,
        tolerance: float,
    ) -> None:
        super().__init__(fmu, api, log, inputs)
        interface = info.interface("ModelExchange")
        self.needs_completed = interface is not None and interface.needs_completed_integrator_step
        self.discrete_inputs = any(v.variability == "discrete" for v in inputs)
        self.next_event: float | None = None
        self.h = step if solver == "Euler" else None
        self._nx = info.number_of_continuous_states
        self._nz = info.number_of_event_indicators
        self._solver_name = solver
        self._tolerance = tolerance
        self._calls = _SolverCalls(api)
        self._solver: Any = None
        self._dirty = False

    def begin(self) -> None:
        self._iterate_events()
        self._check(self.api.enter_continuous_time_mode(), "EnterContinuousTimeMode")
        args = {"nx": self._nx, "nz": self._nz, "input": _NoInput()}
        c = self._calls
        args |= {"get_x": c.get_x, "set_x": c.set_x, "get_dx": c.get_dx, "get_z": c.get_z}
        if self._solver_name == "Euler":
            self._solver = ForwardEuler(**args)
        else:
            from fmpy.sundials import CVodeSolver  # type: ignore[import-untyped]

            self._solver = CVodeSolver(
                get_nominals=c.get_nominals,
                set_time=c.set_time,
                startTime=self.time,
                relativeTolerance=self._tolerance,
                **args,
            )
        self._raise_kept()

    def set_inputs(self, values_at: int) -> None:
        self.change_inputs(lambda: Engine.set_inputs(self, values_at))

    def change_inputs(self, set_inputs: Callable[[], None]) -> None:
        """Set inputs with `set_inputs`: in event mode if some are discrete, else the solver
        restarts from the new inputs at the next advance. (The co-simulation's MeSlave sets
        its inputs through here.)"""
        if self.discrete_inputs:
            self._in_event_mode(set_inputs)
        else:
            set_inputs()
            self._dirty = True

    def moved(self, time: float, next_event: float | None) -> None:
        """The FMU's state was set back to one saved at `time` (a co-simulation's rollback):
        the solver restarts there at the next advance."""
        self.time, self.next_event, self._dirty = time, next_event, True

    def retune(self, values: list[tuple[FmuVariable, Scalar]]) -> None:
        self._in_event_mode(lambda: set_values(self.fmu, self.api.fmi3, values, self.log))

    def close(self) -> None:
        self._solver = None  # FMPy's CVodeSolver frees its memory when collected

    def advance(self, t_end: float) -> None:
        if self._dirty:  # new inputs: restart the solver, as FMPy does at an input event
            self._solver.reset(self.time)
            self._dirty = False
            self._raise_kept()
        eps = 1e-12 * max(1.0, abs(t_end))
        while t_end - self.time > eps:
            if self.next_event is not None and self.next_event <= self.time + eps:
                self._in_event_mode(None)
                continue
            stop = t_end
            if self.next_event is not None and self.next_event < stop:
                stop = self.next_event
            if self.h is not None and stop - self.time > self.h * (1 + 1e-6):
                stop = self.time + self.h
            self._integrate(stop, eps)

    def _integrate(self, stop: float, eps: float) -> None:
        try:
            state_event, _roots, t = self._solver.step(self.time, stop)
        except RuntimeError as err:  # FMPy's CVodeSolver on a failing CVode call
            raise BlueprintError(f"the solver failed at t = {self.time:g} s: {err}") from err
        self._raise_kept()
        self.time = float(t)
        self._check(self.api.set_time(self.time), "SetTime")
        step_event = False
        if self.needs_completed:
            status, step_event, terminate = self.api.completed_integrator_step()
            self._check(_or_terminate(status, terminate), "CompletedIntegratorStep")
        time_event = self.next_event is not None and self.time >= self.next_event - eps
        if state_event or step_event or time_event:
            self._in_event_mode(None)

    def _in_event_mode(self, action: Callable[[], None] | None) -> None:
        """Enter event mode, do `action`, iterate events, back to continuous time."""
        self._check(self.api.enter_event_mode(), "EnterEventMode")
        if action is not None:
            action()
        self._iterate_events()
        self._check(self.api.enter_continuous_time_mode(), "EnterContinuousTimeMode")
        if self._solver is not None:
            self._solver.reset(self.time)
            self._raise_kept()
        self._dirty = False

    def _iterate_events(self) -> None:
        name = "UpdateDiscreteStates" if self.api.fmi3 else "NewDiscreteStates"
        for _ in range(MAX_EVENT_ITERATIONS):
            status, again, terminate, next_event = self.api.update_discrete_states()
            self._check(_or_terminate(status, terminate), name)
            self.next_event = next_event
            if not again:
                return
        raise BlueprintError(f"the event iteration at t = {self.time:g} s does not converge")

    def _check(self, status: int, name: str) -> None:
        if status > WARNING:
            raise fmi_failure(self.prefix + name, status, self.log, f" at t = {self.time:g} s")

    def _raise_kept(self) -> None:
        failure, self._calls.failure = self._calls.failure, None
        if failure is not None:
            self._check(failure[1], failure[0])
