"""A batch co-simulation run: from a System and its FMU files to the recorded rows.

Every FMU is instantiated (FMI 2 or FMI 3 co-simulation), given its parameters and start
values, initialized with the connections exchanged once, stepped from start to end by the
master, then terminated and freed, whatever happened: a failed run leaves no instance, no
loaded library and no extracted folder behind.
"""

from __future__ import annotations

import shutil
import tempfile
import threading
from collections import defaultdict
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from twinlink.domain.errors import InvalidInputError
from twinlink.processors.fmuinfo import Scalar

from .master import Link, Master, Progress, Record, stepping_order, steps
from .model import Port, System
from .results import Result, column_name
from .slaves import CosimRunError, FmuTerminated, Group, Slave

__all__ = ["CosimRunError", "Result", "run"]


def run(
    system: System,
    fmu_paths: Mapping[str, Path],
    *,
    progress: Progress | None = None,
    stop: threading.Event | None = None,
) -> Result:
    """Run `system` as fast as possible and return its recorded rows.

    `fmu_paths` maps each instance's `fmu` (as the file names it) to the FMU file. `progress`
    is called with the fraction done (at most about 100 times, and 1.0 at the end); `stop`,
    once set, ends the run after the current step with the rows so far. Raises
    InvalidInputError for a system this master cannot run, CosimRunError (naming the
    instance) when an FMU fails.
    """
    _check(system, fmu_paths)
    slaves: list[Slave] = []
    workdir = Path(tempfile.mkdtemp(prefix="twinlink-cosim-"))
    try:
        by_name = {i.name: i for i in system.instances}
        for k, name in enumerate(stepping_order(system)):
            path = Path(fmu_paths[by_name[name].fmu])
            slaves.append(Slave(name, path, workdir / str(k)))
        return _simulate(system, slaves, progress, stop)
    finally:
        for slave in reversed(slaves):
            slave.close()
        shutil.rmtree(workdir, ignore_errors=True)


def _check(system: System, fmu_paths: Mapping[str, Path]) -> None:
    algorithm = system.algorithm
    if algorithm.kind != "fixed-step":
        raise InvalidInputError(
            f"the {algorithm.kind} algorithm is not supported yet; use fixed-step"
        )
    if not algorithm.size > 0:
        raise InvalidInputError(f"the step size must be positive, not {algorithm.size}")
    if system.end_time is None or not system.end_time > system.start_time:
        raise InvalidInputError(
            f"a batch run needs an end time after the start time ({system.start_time:g})"
        )
    names = {i.name for i in system.instances}
    for instance in system.instances:
        if instance.fmu not in fmu_paths:
            raise InvalidInputError(
                f"instance {instance.name!r}: no file for its FMU {instance.fmu!r}"
            )
    ports = [c.source for c in system.connections] + [c.target for c in system.connections]
    ports += list(system.parameters)
    ports += [Port(name, "") for name in system.log_variables]
    for port in ports:
        if port.instance not in names:
            raise InvalidInputError(f"{port} names no instance of the system")


def _simulate(
    system: System, slaves: list[Slave], progress: Progress | None, stop: threading.Event | None
) -> Result:
    times = steps(system)
    master, columns = _wire(system, slaves, len(times))
    values: dict[str, list[tuple[str, Scalar]]] = defaultdict(list)
    for port, value in system.parameters.items():
        values[port.instance].append((port.variable, value))
    for slave in slaves:
        slave.set_start_values(values[slave.name])
        slave.enter_initialization(times[0], times[-1])
    master.exchange_initial()
    for slave in slaves:
        slave.exit_initialization()
    ended = ""
    try:
        rows = master.run(times, progress, stop)
        if rows < len(times):
            ended = f"stopped at t = {times[rows - 1]:g} s"
    except FmuTerminated as done:
        rows = int(np.count_nonzero(~np.isnan(master.table[:, 0])))
        ended = str(done)
    if progress is not None and not ended:
        progress(1.0)
    return Result(columns, master.table[:rows], ended)


def _wire(system: System, slaves: list[Slave], rows: int) -> tuple[Master, tuple[str, ...]]:
    """The master over `slaves` with its links and records, and the recorded columns."""
    by_name = {s.name: s for s in slaves}
    # Ports first (each adds its variable to a buffer), then the buffers, then the links.
    pending: dict[str, list[tuple[tuple[Group, int], tuple[Group, int]]]] = defaultdict(list)
    for c in system.connections:
        source = by_name[c.source.instance].port(c.source.variable, into=False)
        target = by_name[c.target.instance].port(c.target.variable, into=True)
        pending[c.target.instance].append((source, target))
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
    table = np.full((rows, len(columns)), np.nan)
    jacobi = system.algorithm.master == "jacobi"
    return Master(slaves, links, _records(recorded), table, jacobi), tuple(columns)


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
