"""The masters' schedules: the Gauss-Seidel order, the fixed step's communication points, and
the var-step master's step sizes."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from twinlink.cosim.master import Master, stepping_order, steps
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.varstep import VarStep


def system(names: str, links: list[str], step: float = 0.1, end: float = 1.0) -> System:
    """`links` as "a>b": an output of a feeds an input of b."""

    def connection(link: str) -> Connection:
        a, b = link.split(">")
        return Connection(Port(a, "y"), Port(b, "u"))

    return System(
        instances=tuple(Instance(n, f"{n}.fmu") for n in names.split()),
        connections=tuple(connection(link) for link in links),
        parameters={},
        log_variables={},
        algorithm=Algorithm("fixed-step", step),
        end_time=end,
    )


@pytest.mark.parametrize(
    ("names", "links", "order"),
    [
        ("c b a", ["a>b", "b>c"], ("a", "b", "c")),  # a chain, whatever the declared order
        ("plant ctrl", ["plant>ctrl", "ctrl>plant"], ("plant", "ctrl")),  # a cycle: declared
        ("ctrl plant", ["plant>ctrl", "ctrl>plant"], ("ctrl", "plant")),
        ("x a b", ["b>a", "a>b", "a>x"], ("a", "x", "b")),  # x, fed by the cycle, waits for a
        ("c d a b", ["a>b", "b>a", "b>c", "c>d", "d>c"], ("a", "b", "c", "d")),  # cycle by cycle
        ("p q", ["p>p"], ("p", "q")),  # feeding itself orders nothing
    ],
)
def test_gauss_seidel_steps_an_instance_after_those_that_feed_it(
    names: str, links: list[str], order: tuple[str, ...]
) -> None:
    assert stepping_order(system(names, links)) == order


def test_the_last_step_is_shorter_when_the_span_is_not_whole_steps() -> None:
    assert steps(system("a", [], step=0.4, end=1.0)) == pytest.approx([0.0, 0.4, 0.8, 1.0])
    points = steps(system("a", [], step=0.1, end=1.0))  # 10 steps despite 0.1's rounding
    assert len(points) == 11 and points[-1] == 1.0


# --- the var-step master's step size control, on instances that are plain functions of time


class Clock:
    """A SlaveLike stand-in whose output is f(its time); its state is its time."""

    def __init__(self, f: Callable[[float], float], *, can_rollback: bool = True) -> None:
        self.name = self.label = "clock"
        self.f, self.can_rollback, self.time = f, can_rollback, 0.0
        self.out = np.zeros(1)
        self.restored = 0
        self.saved: set[int] = set()

    def write(self) -> None:
        pass

    def read(self) -> None:
        self.out[0] = self.f(self.time)

    def step(self, t: float, h: float) -> float:
        assert t == self.time  # a rejected step was rolled back to its start
        self.time = t + h
        return t + h

    def save_state(self) -> object:
        key = len(self.saved) + self.restored * 1_000_000
        self.saved.add(key)
        return (key, self.time)

    def restore_state(self, state: object) -> None:
        assert isinstance(state, tuple)
        self.time = state[1]
        self.restored += 1

    def free_state(self, state: object) -> None:
        assert isinstance(state, tuple)
        self.saved.remove(state[0])


def varstep_run(
    f: Callable[[float], float], low: float, high: float, *, rollback: bool = True
) -> tuple[list[float], VarStep, Clock]:
    clock = Clock(f, can_rollback=rollback)
    master = Master([clock], {}, [], jacobi=True)  # type: ignore[list-item]
    stepper = VarStep(master, Algorithm("var-step", 0.01, low, high), [(clock.out, 0)], 1e-3)
    master.read()
    stepper.start()
    times, t = [0.0], 0.0
    while t < 10.0:
        t = stepper.step(t, 10.0)
        times.append(t)
    return times, stepper, clock


def test_var_step_follows_the_signal_within_its_bounds() -> None:
    times, stepper, clock = varstep_run(math.sin, 0.001, 0.5)
    sizes = np.diff(times)
    assert times[-1] == 10.0 and not clock.saved  # every saved state freed
    assert sizes[:-1].min() >= 0.001 and sizes.max() <= 0.5
    assert np.all(sizes[1:-1] <= 2 * sizes[:-2] * (1 + 1e-12))  # at most doubling
    assert stepper.rejected == clock.restored and stepper.forced == 0
    # shorter where sin bends most (near its peaks) than where it is straight (zero crossings)
    mid = (np.array(times[:-1]) + np.array(times[1:])) / 2
    bent, straight = np.abs(np.sin(mid)) > 0.9, np.abs(np.sin(mid)) < 0.1
    assert sizes[bent].mean() < sizes[straight].mean()


def test_var_step_grows_to_max_size_on_a_straight_line() -> None:
    times, stepper, _ = varstep_run(lambda t: 3.0 * t, 0.001, 0.64)
    sizes = [0.01, 0.01, 0.02, 0.04, 0.08, 0.16, 0.32, 0.64, 0.64]  # the first as given
    assert np.diff(times)[:9].tolist() == pytest.approx(sizes)
    assert stepper.rejected == 0 and times[-1] == 10.0


def test_a_jump_is_stepped_over_at_min_size_and_counted() -> None:
    times, stepper, clock = varstep_run(lambda t: float(t > 5.0), 0.001, 0.5)
    assert stepper.rejected >= 1 and stepper.forced == 1 and clock.restored == stepper.rejected
    jump = int(np.searchsorted(times, 5.0, side="right"))
    assert times[jump] - times[jump - 1] == pytest.approx(0.001)


def test_without_rollback_no_step_is_rejected() -> None:
    times, stepper, clock = varstep_run(lambda t: float(t > 5.0), 0.001, 0.5, rollback=False)
    assert stepper.rejected == 0 and clock.restored == 0 and stepper.forced >= 1
    assert times[-1] == 10.0
