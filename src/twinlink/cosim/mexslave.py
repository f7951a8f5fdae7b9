"""A model exchange FMU in a co-simulation: FMPy's solvers integrate it between
communication points, as the FMU blueprint's ModelExchange engine does.

The FMU has no doStep of its own; the engine (processors/blueprints/_fmu_me.py, reused as
is) holds the inputs constant over a step, integrates with CVode (or forward Euler), and
handles time, state and step events with an event iteration each. Ports, buffers, start
values and closing are those of a co-simulation Slave: only how it is instantiated, how its
inputs are set while running and how it steps differ.
"""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path
from typing import Any, Literal

import fmpy  # type: ignore[import-untyped]
import numpy as np

from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.blueprints._fmu_fmi import TERMINATE, FmuLog, instantiate
from twinlink.processors.blueprints._fmu_me import ModelExchange
from twinlink.processors.fmuinfo import FmuError, inspect_fmu

from .slaves import Buffer, CosimRunError, FmuTerminated, Slave

_log = logging.getLogger("twinlink.cosim")
Solver = Literal["CVode", "Euler"]
DEFAULT_TOLERANCE = 1e-6  # CVode's relative tolerance when the FMU declares none
DEFAULT_EULER_STEP = 1e-3  # Euler's step when the FMU's default experiment has none


class MeSlave(Slave):
    """A model exchange FMU instance, stepped by a solver; a Slave to the master."""

    def __init__(
        self,
        name: str,
        fmu_path: Path,
        unzipdir: Path,
        *,
        solver: Solver = "CVode",
        solver_step: float | None = None,
    ) -> None:
        # Slave.__init__ instantiates co-simulation; the same attributes, for model exchange.
        self.name = name
        self.label = f"instance {name!r} ({fmu_path.name})"
        self.log = FmuLog("off", _log)
        self.initialized = False
        try:
            self.info = inspect_fmu(fmu_path)
        except FmuError as err:
            raise CosimRunError(f"{self.label}: {err}") from err
        if not self.info.model_exchange:
            raise CosimRunError(f"{self.label}: the FMU has no model exchange interface")
        self.fmi3 = self.info.fmi_version.startswith("3")
        with self._errors("cannot be used"):
            fmpy.extract(str(fmu_path), str(unzipdir))
            # read before instantiating: a failure after it would leave the instance unfreed
            me = fmpy.read_model_description(str(unzipdir), validate=False).modelExchange
            self.fmu, self.api = instantiate(self.info, "ModelExchange", unzipdir, self.log, name)
        self.can_rollback = bool(getattr(me, "canGetAndSetFMUstate", False))
        self._outputs = {}
        self._inputs = {}
        self.solver: Solver = solver
        experiment = self.info.default_experiment
        self.solver_step = solver_step or experiment.step or DEFAULT_EULER_STEP
        self.tolerance = experiment.tolerance or DEFAULT_TOLERANCE
        self.engine: ModelExchange | None = None
        self._start = 0.0
        self._written: list[Buffer] = []  # the inputs last set, to restart only on a change

    def enter_initialization(self, start: float, stop: float | None) -> None:
        self._start = start
        super().enter_initialization(start, stop)

    def exit_initialization(self) -> None:
        """Out of initialization (into event mode), then the first event iteration and the
        solver, at the start time."""
        super().exit_initialization()
        inputs = [self.variable(n) for g in self._inputs.values() for n in g.names]
        self.engine = ModelExchange(
            self.fmu, self.api, self.log, inputs, self.info, self.solver,
            self.solver_step, self.tolerance,
        )  # fmt: skip
        self.engine.time = self._start
        with self._errors("failed to start its solver"):
            self.engine.begin()

    def write(self) -> None:
        """Set the inputs; a change of inputs while running restarts the solver (discrete
        inputs are set in event mode), unchanged inputs leave it as it is."""
        engine = self.engine
        if engine is None:  # initialization mode: set as they are
            super().write()
            return
        buffers = [g.buffer for g in self._inputs.values()]
        if len(buffers) == len(self._written) and all(
            np.array_equal(a, b) for a, b in zip(buffers, self._written, strict=True)
        ):
            return
        with self._errors("failed to take its inputs"):
            engine.change_inputs(super().write)
        self._written = [b.copy() for b in buffers]

    def step(self, t: float, h: float) -> float:
        """Integrate from t to t + h with the inputs held; the time reached. FmuTerminated
        when the FMU asks to end the simulation on the way."""
        engine = self.engine
        if engine is None:
            raise CosimRunError(f"{self.label} is not initialized")
        failed, failure = self.log.failed, self.log.failure
        try:
            engine.advance(t + h)
        except BlueprintError as err:
            if self.log.failed == TERMINATE:  # not a failure: the instance can still close
                self.log.failed, self.log.failure = failed, failure
                message = f"{self.label} asked to terminate at t = {engine.time:g} s"
                raise FmuTerminated(message, engine.time) from err
            raise CosimRunError(f"{self.label}: {err}") from err
        return engine.time

    def save_state(self) -> object:
        """The FMU's state, with the solver's time and next time event. The solver restarts
        here too, so a step redone after restore_state is the same step, to the last bit."""
        engine = self.engine
        if not self.can_rollback or engine is None:
            raise CosimRunError(f"{self.label} cannot save its state (canGetAndSetFMUstate)")
        with self._errors("cannot save its state"):
            state = self.fmu.getFMUState() if self.fmi3 else self.fmu.getFMUstate()
        engine.moved(engine.time, engine.next_event)
        return (state, engine.time, engine.next_event)

    def restore_state(self, state: object) -> None:
        """Back to a saved state; the solver restarts from there."""
        fmu_state, time, next_event = _unpack(state)
        assert self.engine is not None  # save_state needed it
        with self._errors("cannot restore its state"):
            if self.fmi3:
                self.fmu.setFMUState(fmu_state)
            else:
                self.fmu.setFMUstate(fmu_state)
        self.engine.moved(time, next_event)
        self._written = []  # set the inputs again: the state holds those saved with it

    def free_state(self, state: object) -> None:
        fmu_state = _unpack(state)[0]
        with self._errors("cannot free a saved state"):
            if self.fmi3:
                self.fmu.freeFMUState(fmu_state)
            else:
                self.fmu.freeFMUstate(fmu_state)

    def close(self) -> None:
        if self.engine is not None:
            with contextlib.suppress(Exception):
                self.engine.close()
        super().close()


def _unpack(state: object) -> tuple[Any, float, float | None]:
    if not (isinstance(state, tuple) and len(state) == 3):
        raise TypeError(f"not a state saved by MeSlave.save_state: {state!r}")
    return state[0], float(state[1]), state[2]
