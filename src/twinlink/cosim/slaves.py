"""One FMU instance of a co-simulation, driven through the FMU blueprint's FMI layer.

The blueprint's FMI layer (loading, the FMU's log, raw calls bound once, typed start
values) is reused as is: it imports nothing of the server. The values a master exchanges
live in numpy buffers, one per FMI type and direction, that the raw get/set calls read and
write in place; a port is a (buffer, index) pair into them.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import fmpy  # type: ignore[import-untyped]
import numpy as np
import numpy.typing as npt

from twinlink.domain.errors import TwinlinkError
from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.blueprints._fmu_fmi import (
    DISCARD,
    EARLY_RETURN,
    FATAL,
    TERMINATE,
    WARNING,
    FmiApi,
    FmuLog,
    fmi_errors,
    fmi_failure,
    instantiate,
    set_values,
    value_for,
)
from twinlink.processors.fmuinfo import FmuError, FmuInfo, FmuVariable, Scalar, inspect_fmu

_log = logging.getLogger("twinlink.cosim")
Buffer = npt.NDArray[Any]


class CosimRunError(TwinlinkError):
    """A co-simulation run failed; the message names the instance (and its FMU) that failed
    and what it said."""

    status = 422


class FmuTerminated(Exception):
    """An FMU asked to end the simulation in a step; `time` is where it got to. Control flow:
    the master finishes that step (its row is recorded, at `time`) and ends the run with it,
    never an error of its own."""

    def __init__(self, message: str, time: float) -> None:
        super().__init__(message)
        self.time = time


@dataclass(slots=True)
class Group:
    """The variables of one FMI type read or written in one call."""

    type: str
    names: list[str] = field(default_factory=list)
    vrs: list[int] = field(default_factory=list)
    buffer: Buffer = field(default_factory=lambda: np.zeros(0))
    call: Callable[[int], int] = field(default=lambda address: 0)  # bound by Slave.bind
    address: int = 0


class Slave:
    """An instantiated FMU: its ports' buffers, read and written by the master."""

    def __init__(self, name: str, fmu_path: Path, unzipdir: Path) -> None:
        self.name = name
        self.label = f"instance {name!r} ({fmu_path.name})"
        self.log = FmuLog("off", _log)
        self.initialized = False
        try:
            self.info: FmuInfo = inspect_fmu(fmu_path)
        except FmuError as err:
            raise CosimRunError(f"{self.label}: {err}") from err
        if not self.info.co_simulation:
            raise CosimRunError(f"{self.label}: the FMU has no co-simulation interface")
        self.fmi3 = self.info.fmi_version.startswith("3")
        with self._errors("cannot be used"):
            fmpy.extract(str(fmu_path), str(unzipdir))
            self.fmu, self.api = instantiate(self.info, "CoSimulation", unzipdir, self.log, name)
            cs = fmpy.read_model_description(str(unzipdir), validate=False).coSimulation
        # FMI 2 canGetAndSetFMUstate, FMI 3 canGetAndSetFMUState: the var-step master's
        # rollback of a rejected step needs it
        self.can_rollback = bool(getattr(cs, "canGetAndSetFMUstate", False))
        self._outputs: dict[str, Group] = {}
        self._inputs: dict[str, Group] = {}

    @contextmanager
    def _errors(self, what: str) -> Iterator[None]:
        """The FMI layer's errors (and FMPy's plain exceptions) as a CosimRunError naming
        the instance."""
        try:
            yield
        except CosimRunError:
            raise
        except Exception as err:  # BlueprintError, or FMPy's plain Exception
            raise CosimRunError(f"{self.label} {what}: {err}") from err

    def variable(self, name: str, *, settable: bool = False) -> FmuVariable:
        var = self.info.variable(name)
        if var is None:
            raise CosimRunError(f"{self.label} has no variable {name!r}")
        if var.type in ("String", "Binary", "Clock") or var.shape:
            raise CosimRunError(
                f"{self.label}: {name} is a {var.type}{' array' if var.shape else ''}; "
                "only scalar numbers and Booleans can be connected or recorded"
            )
        if settable and var.causality not in ("input", "parameter"):
            raise CosimRunError(f"{self.label}: {name} is an {var.causality}, not an input")
        return var

    def port(self, name: str, *, into: bool) -> tuple[Group, int]:
        """The group and index of variable `name` read from (into=False) or written to
        (into=True) the FMU; the buffers exist once `bind` ran."""
        var = self.variable(name, settable=into)
        groups = self._inputs if into else self._outputs
        group = groups.setdefault(var.type, Group(var.type))
        if name not in group.names:
            group.names.append(name)
            group.vrs.append(var.value_reference)
        return group, group.names.index(name)

    def bind(self) -> None:
        """Allocate the buffers and bind the raw get/set calls to them."""
        api: FmiApi = self.api
        for op, groups in (("Get", self._outputs), ("Set", self._inputs)):
            for type_, group in groups.items():
                dtype = api.DTYPES.get(type_)
                if dtype is None:
                    raise CosimRunError(
                        f"{self.label}: variables of type {type_} cannot be exchanged"
                    )
                group.buffer = np.zeros(len(group.vrs), dtype=dtype)
                with self._errors("cannot be used"):
                    group.call = api.accessor(op, type_, group.vrs)
                group.address = group.buffer.ctypes.data

    def set_start_values(self, values: list[tuple[str, Scalar]]) -> None:
        """Parameters and start values, before initialization."""
        typed: list[tuple[FmuVariable, Scalar]] = []
        for name, value in values:
            var = self.variable(name)
            try:
                typed.append((var, value_for(var, value)))
            except BlueprintError as err:
                raise CosimRunError(f"{self.label}: {err}") from err
        with self._errors("refused a start value"):
            set_values(self.fmu, self.fmi3, typed, self.log)

    def enter_initialization(self, start: float, stop: float | None) -> None:
        """`stop` None: an open end (FMI 2 stopTimeDefined false; FMI 3 likewise)."""
        with self._errors("failed to enter initialization"), fmi_errors(self.log):
            if self.fmi3:
                self.fmu.enterInitializationMode(startTime=start, stopTime=stop)
            else:
                self.fmu.setupExperiment(startTime=start, stopTime=stop)
                self.fmu.enterInitializationMode()

    def exit_initialization(self) -> None:
        with self._errors("failed to initialize"), fmi_errors(self.log):
            self.fmu.exitInitializationMode()
        self.initialized = True

    def read(self) -> None:
        for group in self._outputs.values():
            status = group.call(group.address)
            if status > WARNING:
                self._fail(self.api.function("Get", group.type), status)

    def write(self) -> None:
        for group in self._inputs.values():
            status = group.call(group.address)
            if status > WARNING:
                self._fail(self.api.function("Set", group.type), status)

    def step(self, t: float, h: float) -> float:
        """Step from t by h; the time reached: t + h, or less after an FMI 3 early return or
        an fmi2Discard (its last successful time). Raises FmuTerminated, CosimRunError."""
        status = self.api.do_step(t, h)
        if status <= WARNING:
            return t + h
        if status in (DISCARD, TERMINATE, EARLY_RETURN):
            terminated, reached = self.api.discarded(t)
            reached = min(max(reached, t), t + h)
            if status == TERMINATE or terminated:
                raise FmuTerminated(
                    f"{self.label} asked to terminate at t = {reached:g} s "
                    f"(in the step from t = {t:g} s)",
                    reached,
                )
            return reached
        self._fail(f"{self.api.prefix}DoStep", status, f" at t = {t:g} s")
        return t  # not reached: _fail raises

    def save_state(self) -> object:
        """The FMU's whole state (fmi2GetFMUstate / fmi3GetFMUState), for restore_state."""
        with self._errors("cannot save its state"), fmi_errors(self.log):
            return self.fmu.getFMUState() if self.fmi3 else self.fmu.getFMUstate()

    def restore_state(self, state: object) -> None:
        with self._errors("cannot restore its state"), fmi_errors(self.log):
            if self.fmi3:
                self.fmu.setFMUState(state)
            else:
                self.fmu.setFMUstate(state)

    def free_state(self, state: object) -> None:
        with self._errors("cannot free a saved state"), fmi_errors(self.log):
            if self.fmi3:
                self.fmu.freeFMUState(state)
            else:
                self.fmu.freeFMUstate(state)

    def _fail(self, function: str, status: int, when: str = "") -> None:
        err = fmi_failure(function, status, self.log, when)
        raise CosimRunError(f"{self.label}: {err}")

    def close(self) -> None:
        """Terminate and free the instance (and its library); never raises. After a fatal
        status no call is allowed: the instance is left as it is, as the blueprint does."""
        steps: list[tuple[str, Callable[[], Any]]] = []
        if self.initialized and not self.log.failed:
            steps.append(("terminate", self.fmu.terminate))
        if self.log.failed < FATAL:
            steps.append(("freeInstance", self.fmu.freeInstance))
        for what, call in steps:
            try:
                call()
            except Exception as err:  # closing must not hide the run's own error
                _log.warning("%s: %s failed: %s (%s)", self.label, what, err, self.log.tail())
