"""The fixed-step master algorithms: Jacobi and Gauss-Seidel.

Jacobi: every instance steps from the outputs all of them had at the start of the step.
Gauss-Seidel: instances step one after another, in an order following the connections, and
each sees the outputs of those already stepped to the end of this step (the usual choice:
as cheap, and closer to the monolithic solution for the same step).

A connection is a copy between two numpy buffers (see slaves.py), so a macro step is one raw
FMI call per instance and type and direction plus a few item copies; recording is one numpy
assignment per instance and type.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .model import System
from .slaves import Buffer, Slave

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
    assert end is not None  # runner.run checks it
    n = max(1, math.ceil((end - start) / h - 1e-9))
    return [min(start + k * h, end) for k in range(n + 1)]


class Master:
    """Steps the slaves with the system's algorithm and records a row per communication point."""

    def __init__(
        self,
        slaves: Sequence[Slave],
        incoming: dict[str, list[Link]],
        records: Sequence[Record],
        table: npt.NDArray[np.float64],
        jacobi: bool,
    ) -> None:
        self.slaves = slaves  # in stepping order
        self.incoming = [incoming.get(s.name, []) for s in slaves]
        self.records = records
        self.table = table
        self.jacobi = jacobi

    def exchange_initial(self) -> None:
        """In initialization mode: inputs from outputs, in stepping order."""
        for slave, links in zip(self.slaves, self.incoming, strict=True):
            _copy(links)
            slave.write()
            slave.read()

    def record(self, row: int, t: float) -> None:
        out = self.table[row]
        out[0] = t
        for r in self.records:
            out[r.columns] = r.buffer[r.indexes]

    def run(
        self, times: Sequence[float], progress: Progress | None, stop: threading.Event | None
    ) -> int:
        """Step from times[0] to times[-1], recording each point; returns the rows recorded
        (fewer than len(times) if stopped). Raises FmuTerminated or CosimRunError."""
        for slave in self.slaves:
            slave.read()
        self.record(0, times[0])
        pairs = list(zip(self.slaves, self.incoming, strict=True))
        every = max(1, (len(times) - 1) // 100)
        for k in range(1, len(times)):
            if stop is not None and stop.is_set():
                return k
            t, h = times[k - 1], times[k] - times[k - 1]
            if self.jacobi:
                for _, links in pairs:
                    _copy(links)
                for slave, _ in pairs:
                    slave.write()
                    slave.step(t, h)
                for slave, _ in pairs:
                    slave.read()
            else:
                for slave, links in pairs:
                    _copy(links)
                    slave.write()
                    slave.step(t, h)
                    slave.read()
            self.record(k, times[k])
            if progress is not None and k % every == 0:
                progress(k / (len(times) - 1))
        return len(times)


def _copy(links: list[Link]) -> None:
    for link in links:
        link.target[link.ti] = link.source[link.si]
