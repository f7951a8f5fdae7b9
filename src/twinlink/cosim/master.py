"""The master algorithms' macro step: Jacobi and Gauss-Seidel (the step's size is the
caller's: a fixed grid in session.py, a variable one in varstep.py).

Jacobi: every instance steps from the outputs all of them had at the start of the step.
Gauss-Seidel: instances step one after another, in an order following the connections, and
each sees the outputs of those already stepped to the end of this step (the usual choice:
as cheap, and closer to the monolithic solution for the same step).

An instance asking to terminate does not cut the step short for the others: they finish it,
every output is read, and the step's row is recorded (as the FMU blueprint keeps the
terminating step's outputs); the run then ends.

A connection is a copy between two numpy buffers (see slaves.py), so a macro step is one raw
FMI call per instance and type and direction plus a few item copies; recording is one numpy
assignment per instance and type.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .model import System
from .protocol import SlaveLike
from .slaves import Buffer, FmuTerminated

Progress = Callable[[float], None]


@dataclass(frozen=True, slots=True)
class Link:
    """One connection: copy source[si] into target[ti] before the target steps."""

    source: Buffer
    si: int
    target: Buffer
    ti: int


@dataclass(frozen=True, slots=True)
class Record:
    """Columns `columns` of a row take `buffer[indexes]`."""

    buffer: Buffer
    indexes: npt.NDArray[np.intp]
    columns: npt.NDArray[np.intp]


def stepping_order(system: System) -> tuple[str, ...]:
    """The instances in Gauss-Seidel order: an instance after those that feed it (Kahn's
    algorithm, ties in declared order). A cycle of connections (two coupled FMUs) is broken
    at its first instance in declared order, once nothing outside the cycle feeds it."""
    names = [i.name for i in system.instances]
    feeders: dict[str, set[str]] = {name: set() for name in names}
    for c in system.connections:
        if c.source.instance != c.target.instance:
            feeders[c.target.instance].add(c.source.instance)
    order: list[str] = []
    while len(order) < len(names):
        placed = set(order)
        left = [n for n in names if n not in placed]
        ready = [n for n in left if feeders[n] <= placed]
        order.append(ready[0] if ready else _cycle_start(left, feeders, placed))
    return tuple(order)


def _cycle_start(left: list[str], feeders: dict[str, set[str]], placed: set[str]) -> str:
    """The first instance (in declared order) of a cycle that only feeds itself: every
    instance feeding it, directly or not, is placed or in its cycle."""
    ancestors: dict[str, set[str]] = {}
    for name in left:
        seen: set[str] = set()
        todo = [f for f in feeders[name] if f not in placed]
        while todo:
            f = todo.pop()
            if f not in seen:
                seen.add(f)
                todo.extend(g for g in feeders[f] if g not in placed)
        ancestors[name] = seen
    for name in left:
        if name in ancestors[name] and all(name in ancestors[a] for a in ancestors[name]):
            return name
    return left[0]  # not reached: some cycle is fed by nothing outside it


def steps(system: System) -> list[float]:
    """The communication points from start to end time: a fixed step, the last one shorter
    if the span is not a whole number of steps."""
    start, end, h = system.start_time, system.end_time, system.algorithm.size
    assert end is not None  # Session checks it
    n = max(1, math.ceil((end - start) / h - 1e-9))
    return [min(start + k * h, end) for k in range(n + 1)]


class Master:
    """Steps the slaves, in stepping order, with the system's algorithm (Jacobi or
    Gauss-Seidel) and fills a row with the recorded outputs."""

    def __init__(
        self,
        slaves: Sequence[SlaveLike],
        incoming: dict[str, list[Link]],
        records: Sequence[Record],
        jacobi: bool,
    ) -> None:
        self.slaves = slaves  # in stepping order
        self.incoming = [incoming.get(s.name, []) for s in slaves]
        self.records = records
        self.jacobi = jacobi
        self.terminated: FmuTerminated | None = None  # the first FMU that asked to end
        self.short: SlaveLike | None = None  # the last slave that did not reach a step's end
        self._pairs = list(zip(self.slaves, self.incoming, strict=True))

    def exchange_initial(self) -> None:
        """In initialization mode: inputs from outputs, in stepping order."""
        for slave, links in self._pairs:
            _copy(links)
            slave.write()
            slave.read()

    def read(self) -> None:
        for slave in self.slaves:
            slave.read()

    def fill(self, row: npt.NDArray[np.float64], t: float) -> None:
        row[0] = t
        for r in self.records:
            row[r.columns] = r.buffer[r.indexes]

    def step(self, t: float, h: float) -> float:
        """One macro step from t by h with every slave, their outputs read at its end;
        returns the earliest time a slave reached (t + h unless one returned early,
        discarded or terminated). An FMU asking to terminate does not stop the others'
        step: it is kept in `terminated`, and the step's row is recorded as usual."""
        reached = t + h
        if self.jacobi:
            for links in self.incoming:
                _copy(links)
            for slave in self.slaves:
                slave.write()
                try:
                    got = slave.step(t, h)
                except FmuTerminated as done:
                    self.terminated = self.terminated or done
                    got = done.time
                if got < reached:
                    reached, self.short = got, slave
            for slave in self.slaves:
                slave.read()
        else:
            for slave, links in self._pairs:
                _copy(links)
                slave.write()
                try:
                    got = slave.step(t, h)
                except FmuTerminated as done:
                    self.terminated = self.terminated or done
                    got = done.time
                if got < reached:
                    reached, self.short = got, slave
                slave.read()
        return reached


def _copy(links: list[Link]) -> None:
    for link in links:
        link.target[link.ti] = link.source[link.si]
