"""Real-time pacing: a co-simulation stepped so that simulated time follows the wall clock
(`factor` 1.0), or runs `factor` times faster (2.0) or slower (0.5).

Each step has an absolute deadline on a monotonic clock: the wall time at the start plus
the step's start time since the first step, divided by the factor. Deadlines come from the
simulated time itself, never from the previous step's end, so nothing drifts: a late step
does not push the ones after it, which run as soon as they can until the run is on time
again. A step whose deadline has passed when its turn comes is started at once (no sleep)
and counted as late; its lateness is kept with everyone else's, so a run that fell behind
says so in its p99 and max instead of hiding it.

How a step waits for its deadline, measured on the project's shared 2-core VM at 1 kHz:
`time.sleep` alone woke 80-100 us late at the median (the kernel's timer slack is 50 us)
and 140-250 us at the p99; sleeping until SPIN_NS before the deadline, with the thread's
timer slack lowered to 1 us, then spinning on the clock, started the msd pair's steps with
a p99 of 2-3 us at a load average of 1, for about 20 % of one core at 1 kHz, the steps
included (the spin is at most SPIN_NS a step, so less at lower rates). What is left is
the scheduler: a thread that has no CPU at its deadline starts late whatever it does; on a
busy machine that is the p99 (milliseconds), which only real-time priority (chrt -f)
removes.
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import sys
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

SPIN_NS = 200_000  # spin this long before a deadline instead of sleeping through it
LONG_SLEEP_S = 0.05  # a long wait sleeps in pieces this long, to see a stop in time
_FINE_BINS = 10_000  # lateness to 10 ms kept to the microsecond...
_COARSE_BINS = 10_000  # ...and to 10 s to the millisecond; beyond, counted (and the max)
_PR_SET_TIMERSLACK, _PR_GET_TIMERSLACK = 29, 30

Row = npt.NDArray[np.float64]
Clock = Callable[[], int]  # nanoseconds on a monotonic clock
Sleep = Callable[[float], None]  # seconds


class Steppable(Protocol):
    """What pacing needs of a co-simulation (session.Session is one): the current
    communication point, and one step to the next (its row; None once the run ended)."""

    @property
    def time(self) -> float: ...

    def step(self) -> Row | None: ...


@dataclass(frozen=True, slots=True)
class Jitter:
    """How late the steps of a paced run started: each step's actual start minus its
    deadline, in milliseconds. `late` counts the steps whose deadline had already passed
    when their turn came (the run was behind: they started without waiting)."""

    steps: int
    late: int
    p50: float
    p99: float
    max: float

    def __str__(self) -> str:
        behind = f", {self.late} late (the run was behind)" if self.late else ""
        return (
            f"{self.steps} steps, start jitter p50 {self.p50:.3f} ms, p99 {self.p99:.3f} ms, "
            f"max {self.max:.3f} ms{behind}"
        )


class Lateness:
    """Lateness counted in fixed bins: a run of days at 1 kHz keeps the same 160 kB, and
    a percentile is exact to the microsecond up to 10 ms, to the millisecond up to 10 s."""

    def __init__(self) -> None:
        self.fine = [0] * _FINE_BINS  # by microsecond
        self.coarse = [0] * _COARSE_BINS  # by millisecond
        self.beyond = 0
        self.count = 0
        self.late = 0
        self.max_ns = 0

    def add(self, ns: int, late: bool) -> None:
        self.count += 1
        self.late += late
        if ns > self.max_ns:
            self.max_ns = ns
        us = ns // 1000
        if us < _FINE_BINS:
            self.fine[max(us, 0)] += 1
        elif us // 1000 < _COARSE_BINS:
            self.coarse[us // 1000] += 1
        else:
            self.beyond += 1

    def percentile(self, q: float) -> float:
        """The smallest lateness (ms) that at least `q` percent of the steps did not exceed
        (nearest rank), to the bin's resolution; 0.0 with no steps."""
        if not self.count:
            return 0.0
        rank = max(1, math.ceil(q / 100 * self.count))
        seen = 0
        for us, n in enumerate(self.fine):
            seen += n
            if seen >= rank:
                return us / 1000
        for ms, n in enumerate(self.coarse):
            seen += n
            if seen >= rank:
                return float(ms)
        return self.max_ns / 1e6

    def jitter(self) -> Jitter:
        return Jitter(
            self.count, self.late, self.percentile(50), self.percentile(99), self.max_ns / 1e6
        )


def run_paced(
    session: Steppable,
    factor: float,
    stop: threading.Event,
    on_row: Callable[[Row], None],
    *,
    clock: Clock = time.perf_counter_ns,
    sleep: Sleep = time.sleep,
    spin_ns: int = SPIN_NS,
) -> Jitter:
    """Step an initialized `session` until it ends or `stop` is set, each step started at
    its deadline: the wall time of the first step plus (its start time - the first step's)
    / `factor`. `on_row` gets each step's row as it comes (it runs on the step's time). The
    caller initializes the session and handles the row at the start time itself.

    Sleeps never wait on `stop` (a signal handler may set it; Event.wait holds the lock
    Event.set takes): long waits sleep in pieces and look at it between them. Another
    Python thread busy in the same process delays a step by up to the interpreter's switch
    interval (5 ms) when it holds the GIL at the deadline: the worker has none. `clock` and
    `sleep` are for tests."""
    if not (factor > 0 and math.isfinite(factor)):
        raise ValueError(f"the real-time factor must be a positive number, not {factor}")
    lateness = Lateness()
    t0 = session.time
    scale = 1e9 / factor
    with _fine_timer_slack():
        start = clock()
        while not stop.is_set():
            deadline = start + round((session.time - t0) * scale)
            behind = clock() >= deadline and lateness.count > 0  # the first: at the start
            if not behind and not _wait_until(deadline, clock, sleep, spin_ns, stop):
                break
            started = clock()
            row = session.step()
            if row is None:  # nothing was stepped
                break
            lateness.add(started - deadline, behind)
            on_row(row)
    return lateness.jitter()


def _wait_until(
    deadline: int, clock: Clock, sleep: Sleep, spin_ns: int, stop: threading.Event
) -> bool:
    """Sleep until `spin_ns` before `deadline`, then spin to it; False if `stop` was set
    meanwhile."""
    while (left := deadline - spin_ns - clock()) > 0:
        if stop.is_set():
            return False
        sleep(min(left / 1e9, LONG_SLEEP_S))
    while clock() < deadline:
        pass
    return not stop.is_set()


@contextlib.contextmanager
def _fine_timer_slack() -> Iterator[None]:
    """This thread's timer slack lowered to 1 us while pacing (Linux; elsewhere nothing):
    the kernel's default 50 us would make every sleep wake up to 50 us late, which the spin
    would then have to cover."""
    prctl = _prctl()
    if prctl is None:
        yield
        return
    before = prctl(_PR_GET_TIMERSLACK, 0, 0, 0, 0)
    prctl(_PR_SET_TIMERSLACK, 1000, 0, 0, 0)
    try:
        yield
    finally:
        if before > 0:
            prctl(_PR_SET_TIMERSLACK, before, 0, 0, 0)


def _prctl() -> Callable[..., int] | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        prctl: Callable[..., int] = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    return prctl
