"""An opened co-simulation, stepped by whoever drives it: the batch runner (runner.run), the
paced runner (pacing.py), the processor blueprint (mode 3, inputs from live data).

`Session(system, fmu_paths)` checks the system (times, step sizes, ports naming instances,
algebraic loops), opens every instance (kinds.open_slave), wires the connections and the
recorded columns, and sets the parameters; `initialize()` enters and leaves initialization
mode with the connections exchanged once and gives the row at the start time; each `step()`
gives the row of one macro step, until `None` once the end time is reached or an FMU asked to
terminate. `close()` (or leaving `with Session(...)`) terminates and frees every instance and
removes the extracted files, whatever happened.

A row is `[t, v1, v2, ...]` in the order of `columns` ("time" then Maestro's names of the
recorded variables), a new float64 array per step that the caller may keep.
"""

from __future__ import annotations

import logging
import math
import shutil
import tempfile
from collections import defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import TracebackType

import fmpy  # type: ignore[import-untyped]
import numpy as np
import numpy.typing as npt

from twinlink.domain.errors import InvalidInputError
from twinlink.processors.fmuinfo import Scalar

from .constraints import Constraints
from .constraints import prepare as prepare_constraints
from .graph import algebraic_loops, describe_loop, feedthrough_of
from .kinds import open_slave
from .master import Link, Master, Record, stepping_order
from .model import Port, System
from .protocol import SlaveLike
from .results import column_name
from .slaves import Buffer, CosimRunError, Group
from .varstep import TOLERANCE, VarStep

__all__ = ["CosimRunError", "Session", "check"]

_log = logging.getLogger("twinlink.cosim")
Row = npt.NDArray[np.float64]


class Session:
    """An opened co-simulation stepped by whoever drives it (batch runner, paced runner,
    processor blueprint)."""

    def __init__(
        self,
        system: System,
        fmu_paths: Mapping[str, Path],
        *,
        external_inputs: Sequence[Port] = (),
        tolerance: float | None = None,
        workdir: Path | None = None,
    ) -> None:
        """`tolerance`: the var-step master's relative tolerance (varstep.py; None: the
        algorithm's, else varstep.TOLERANCE). The FMUs are
        extracted into a new folder in `workdir` (default: the system's temporary folder).

        Raises InvalidInputError for a system that cannot run (before any FMU is loaded,
        except an algebraic loop: found from the FMUs' own feedthrough once they are open),
        CosimRunError naming the instance whose FMU cannot be used."""
        check(system, fmu_paths, external_inputs)
        self.system = system
        self.time = system.start_time
        self.ended = ""
        self.steps = 0  # macro steps taken (var-step: accepted ones; varstep has the rest)
        self.warnings: list[str] = []  # what the run does not do as the file asks
        self._slaves: list[SlaveLike] = []
        self._workdir = Path(tempfile.mkdtemp(prefix="twinlink-cosim-", dir=workdir))
        self._initialized = False
        self._done = False
        try:
            by_name = {i.name: i for i in system.instances}
            for k, name in enumerate(stepping_order(system)):
                instance = by_name[name]
                path = Path(fmu_paths[instance.fmu])
                self._slaves.append(open_slave(instance, path, self._workdir / str(k)))
            feedthrough = _Feedthrough(system, fmu_paths)
            _refuse_loops(system, feedthrough)
            constraints = prepare_constraints(system.algorithm, self._slaves)
            self._master, self.columns, self._external = _wire(
                system, self._slaves, external_inputs
            )
            values: dict[str, list[tuple[str, Scalar]]] = defaultdict(list)
            for port, value in system.parameters.items():
                values[port.instance].append((port.variable, value))
            for slave in self._slaves:
                slave.set_start_values(values[slave.name])
            self.varstep = self._varstep(feedthrough, constraints, tolerance)
        except BaseException:
            self.close()
            raise
        self._ncols = len(self.columns)
        self._h = system.algorithm.size
        self._last = _last_step(system)  # the index of the last fixed step, None: open end

    def _varstep(
        self, feedthrough: _Feedthrough, constraints: Constraints, tolerance: float | None
    ) -> VarStep | None:
        """The var-step master over the wired instances (None for a fixed step), with a
        warning for what it cannot do as the file asks."""
        system = self.system
        if system.algorithm.kind != "var-step":
            return None
        watch = _watched(system, feedthrough, self._slaves)
        if tolerance is None:
            tolerance = system.algorithm.tolerance or TOLERANCE
        varstep = VarStep(self._master, system.algorithm, watch, tolerance, constraints)
        if (watch or constraints.checks) and not varstep.rollback:
            self._warn(_no_rollback(self._slaves))
        for note in constraints.warnings:
            self._warn(note)
        return varstep

    def __enter__(self) -> Session:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        err: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def initialize(self) -> Row:
        """Initialize every instance (start values set, connections exchanged once in
        initialization mode) and return the row at the start time."""
        end = self.system.end_time
        for slave in self._slaves:
            slave.enter_initialization(self.time, end)
        self._master.exchange_initial()
        for slave in self._slaves:
            slave.exit_initialization()
        self._initialized = True
        self._master.read()
        if self.varstep is not None:
            self.varstep.start(self.time)
        row = np.empty(self._ncols)
        self._master.fill(row, self.time)
        return row

    def set_inputs(self, values: Mapping[Port, float | int | bool]) -> None:
        """Set external inputs (those given to the constructor); they hold until set again
        and reach their FMUs at the next step."""
        for port, value in values.items():
            target = self._external.get(port)
            if target is None:
                known = ", ".join(str(p) for p in self._external) or "none"
                raise InvalidInputError(
                    f"{port} is not an external input of this co-simulation (they are: {known})"
                )
            buffer, index = target
            buffer[index] = value

    def step(self) -> Row | None:
        """One macro step; its row. None once the end time is reached or an FMU asked to
        terminate (`ended` then says which and when; the terminating step's row is returned
        first, at the time that FMU reached)."""
        if self._done:
            return None
        if not self._initialized:
            raise RuntimeError("Session.initialize() must be called before step()")
        try:
            return self._step()
        except BaseException:
            self._done = True  # an instance failed: nothing more can be stepped
            raise

    def _step(self) -> Row:
        t, k, end, master = self.time, self.steps + 1, self.system.end_time, self._master
        if self.varstep is not None:
            t_next = self.varstep.step(t, end)
            last = end is not None and t_next >= end
        else:
            t_next = self.system.start_time + k * self._h
            if end is not None and t_next > end:
                t_next = end
            reached = master.step(t, t_next - t)
            if reached < t_next - 4 * math.ulp(t_next):
                if master.terminated is None:
                    raise _cut_short(master, t)
                t_next = reached
            last = self._last is not None and k >= self._last
        row = np.empty(self._ncols)
        master.fill(row, t_next)
        self.time, self.steps = t_next, k
        if master.terminated is not None:
            self.ended = str(master.terminated)
            self._done = True
        elif last:
            self._done = True
        return row

    def _warn(self, message: str) -> None:
        self.warnings.append(message)
        _log.warning("%s", message)

    def close(self) -> None:
        """Terminate and free every instance and remove the extracted files; never raises,
        and a second call does nothing."""
        slaves, self._slaves = self._slaves, []
        for slave in reversed(slaves):
            try:
                slave.close()
            except Exception as err:  # a slave's close should not raise; never let it
                _log.warning("%s: closing failed: %s", slave.label, err)
        shutil.rmtree(self._workdir, ignore_errors=True)


def check(
    system: System, fmu_paths: Mapping[str, Path], external_inputs: Sequence[Port] = ()
) -> None:
    """What can be checked of a system without its FMUs; InvalidInputError saying what."""
    algorithm = system.algorithm
    if not algorithm.size > 0:
        raise InvalidInputError(f"the step size must be positive, not {algorithm.size}")
    if algorithm.kind == "var-step":
        low = algorithm.min_size or algorithm.size
        high = algorithm.max_size or algorithm.size
        if not 0 < low <= algorithm.size <= high:
            raise InvalidInputError(
                f"a var-step algorithm needs 0 < min_size ({low:g}) <= size "
                f"({algorithm.size:g}) <= max_size ({high:g})"
            )
    if system.end_time is not None and not system.end_time > system.start_time:
        raise InvalidInputError(
            f"the end time ({system.end_time:g}) must be after the start time "
            f"({system.start_time:g})"
        )
    names = {i.name for i in system.instances}
    for instance in system.instances:
        if instance.fmu not in fmu_paths:
            raise InvalidInputError(
                f"instance {instance.name!r}: no file for its FMU {instance.fmu!r}"
            )
    targets = {c.target for c in system.connections}
    ports = [c.source for c in system.connections] + list(targets)
    ports += list(system.parameters) + list(external_inputs)
    ports += [Port(name, "") for name in system.log_variables]
    ports += [p for c in system.algorithm.constraints for p in c.ports]
    for port in ports:
        if port.instance not in names:
            raise InvalidInputError(f"{port} names no instance of the system")
    for port in external_inputs:
        if port in targets:
            raise InvalidInputError(
                f"{port} is fed by a connection; it cannot also be an external input"
            )


def _last_step(system: System) -> int | None:
    """The number of fixed steps from start to end (the last one shorter if the span is not a
    whole number of steps), as master.steps counts them; None for an open end."""
    if system.end_time is None:
        return None
    span = (system.end_time - system.start_time) / system.algorithm.size
    return max(1, math.ceil(span - 1e-9))


class _Feedthrough:
    """Per instance, what each output depends on directly (graph.Feedthrough), from its FMU's
    ModelStructure, each FMU read once."""

    def __init__(self, system: System, fmu_paths: Mapping[str, Path]) -> None:
        self._paths = {i.name: Path(fmu_paths[i.fmu]) for i in system.instances}
        self._cache: dict[Path, dict[str, set[str]] | None] = {}

    def __call__(self, instance: str) -> Mapping[str, set[str]] | None:
        path = self._paths[instance]
        if path not in self._cache:
            try:
                md = fmpy.read_model_description(str(path), validate=False)
                self._cache[path] = feedthrough_of(md)
            except Exception:  # opened once already; unknown counts as direct
                self._cache[path] = None
        return self._cache[path]


def _refuse_loops(system: System, feedthrough: _Feedthrough) -> None:
    """InvalidInputError naming the algebraic loops, from each FMU's declared feedthrough:
    a master stepping FMUs one value per step cannot solve them."""
    loops = algebraic_loops(system, feedthrough)
    if loops:
        named = "; ".join(describe_loop(loop) for loop in loops)
        raise InvalidInputError(
            f"the connections form {'an algebraic loop' if len(loops) == 1 else 'algebraic loops'}"
            f" (outputs depending directly on inputs they feed): {named}. The masters cannot "
            "solve them; cut each loop, e.g. with an FMU whose output depends on a state"
        )


def _watched(
    system: System, feedthrough: _Feedthrough, slaves: Sequence[SlaveLike]
) -> list[tuple[Buffer, int]]:
    """The connected outputs the var-step master's error estimate follows: those that depend
    on no input directly (an output with feedthrough read after a step still reflects the
    inputs held from its start, a lag that changes with the step size, not an error a
    smaller step removes); all connected outputs when every one has feedthrough."""
    sources = list(dict.fromkeys(c.source for c in system.connections))
    stateful = []
    for port in sources:
        deps = feedthrough(port.instance)
        if deps is not None and port.variable in deps and not deps[port.variable]:
            stateful.append(port)
    by_name = {s.name: s for s in slaves}
    out = []
    for port in stateful or sources:
        group, index = by_name[port.instance].port(port.variable, into=False)
        out.append((group.buffer, index))
    return out


def _no_rollback(slaves: Sequence[SlaveLike]) -> str:
    names = ", ".join(s.label for s in slaves if not s.can_rollback)
    return (
        f"not every instance can save and restore its state ({names}: no "
        "canGetAndSetFMUstate): the var-step master adapts its step but cannot reject one, "
        "so a step over tolerance is kept and only the next one is smaller"
    )


def _cut_short(master: Master, t: float) -> CosimRunError:
    who = master.short.label if master.short is not None else "an instance"
    return CosimRunError(
        f"{who} ended the step from t = {t:g} s early (an FMI 3 early return or an "
        "fmi2Discard); a fixed-step master cannot continue from a step cut short: use the "
        "var-step algorithm"
    )


def _wire(
    system: System, slaves: Sequence[SlaveLike], external: Sequence[Port]
) -> tuple[Master, tuple[str, ...], dict[Port, tuple[Buffer, int]]]:
    """The master over `slaves` with its links and records, the recorded columns and the
    external inputs' buffers."""
    by_name = {s.name: s for s in slaves}
    # Ports first (each adds its variable to a buffer), then the buffers, then the links.
    pending: dict[str, list[tuple[tuple[Group, int], tuple[Group, int]]]] = defaultdict(list)
    for c in system.connections:
        source = by_name[c.source.instance].port(c.source.variable, into=False)
        target = by_name[c.target.instance].port(c.target.variable, into=True)
        pending[c.target.instance].append((source, target))
    inputs = {p: by_name[p.instance].port(p.variable, into=True) for p in external}
    columns = ["time"]
    recorded = []
    for instance, variables in system.log_variables.items():
        for variable in variables:
            recorded.append(by_name[instance].port(variable, into=False))
            columns.append(column_name(system, Port(instance, variable)))
    for slave in slaves:
        slave.bind()
    links = {
        name: [Link(sg.buffer, si, tg.buffer, ti) for (sg, si), (tg, ti) in pairs]
        for name, pairs in pending.items()
    }
    jacobi = system.algorithm.master == "jacobi"
    master = Master(slaves, links, _records(recorded), jacobi)
    external_buffers = {p: (g.buffer, i) for p, (g, i) in inputs.items()}
    for port, (buffer, index) in external_buffers.items():
        # until set, an external input keeps the value the file or the FMU starts it with
        start = system.parameters.get(port)
        if start is None:
            var = by_name[port.instance].info.variable(port.variable)
            start = var.start if var is not None else None
        if isinstance(start, (bool, int, float)):
            buffer[index] = start
    return master, tuple(columns), external_buffers


def _records(recorded: list[tuple[Group, int]]) -> list[Record]:
    """Recorded ports grouped by buffer, so a row is one numpy assignment per buffer."""
    groups: dict[int, tuple[Group, list[int], list[int]]] = {}
    for column, (group, index) in enumerate(recorded, start=1):
        entry = groups.setdefault(id(group), (group, [], []))
        entry[1].append(index)
        entry[2].append(column)
    return [
        Record(group.buffer, np.array(ix, dtype=np.intp), np.array(cols, dtype=np.intp))
        for group, ix, cols in groups.values()
    ]
