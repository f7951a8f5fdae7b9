"""Real-time pacing (cosim/pacing.py) on a fake clock: steps start at absolute deadlines
(no drift whatever the steps cost or the sleeps overshoot), the factor scales them, a run
that fell behind starts its steps at once and counts them late, a stop ends even a long
wait, and the lateness percentiles. No assertion here depends on the real clock."""

from __future__ import annotations

import ctypes
import sys
import threading

import numpy as np
import pytest

from twinlink.cosim.pacing import LONG_SLEEP_S, SPIN_NS, Jitter, Lateness, run_paced

MS = 1_000_000  # ns
TICK = 100  # ns a clock reading costs on the fake clock


class FakeClock:
    """A monotonic clock in ns that moves by TICK per reading, by what is slept plus
    `oversleep` (a kernel waking a thread late), and by what a step costs."""

    def __init__(self, oversleep_ns: int = 0) -> None:
        self.now = 5_000_000_000  # not 0: deadlines are relative to the start
        self.oversleep_ns = oversleep_ns
        self.sleeps: list[tuple[int, float]] = []  # (when, seconds)

    def __call__(self) -> int:
        self.now += TICK
        return self.now

    def sleep(self, seconds: float) -> None:
        assert seconds > 0
        self.sleeps.append((self.now, seconds))
        self.now += round(seconds * 1e9) + self.oversleep_ns


class FakeSession:
    """Steps of `h` simulated seconds from t = 2.0 to `end`; step k costs costs(k) ns of
    the fake clock, and each step's start on that clock is kept."""

    def __init__(self, clock: FakeClock, h: float, end: float, cost_ns: int = 50_000) -> None:
        self.clock = clock
        self.h = h
        self.end = end
        self.time = 2.0
        self.k = 0
        self.costs: dict[int, int] = {}
        self.default_cost = cost_ns
        self.started: list[int] = []
        self.on_step: dict[int, threading.Event] = {}  # set this event at step k

    def step(self) -> np.ndarray | None:
        if self.time >= self.end - 1e-12:
            return None
        self.started.append(self.clock.now)
        self.k += 1
        self.clock.now += self.costs.get(self.k, self.default_cost)
        self.time = 2.0 + self.k * self.h
        if self.k in self.on_step:
            self.on_step[self.k].set()
        return np.array([self.time, 10 * self.time])


def paced(
    session: FakeSession, clock: FakeClock, factor: float = 1.0, stop: threading.Event | None = None
) -> tuple[Jitter, list[np.ndarray], int]:
    rows: list[np.ndarray] = []
    start = clock.now
    jitter = run_paced(
        session, factor, stop or threading.Event(), rows.append, clock=clock, sleep=clock.sleep
    )
    return jitter, rows, start


def offsets(session: FakeSession, start: int, period_ns: float) -> list[float]:
    """Each step's start minus its deadline, in ns (the deadline taken from the first
    clock reading, a TICK after `start`)."""
    return [s - (start + TICK + k * period_ns) for k, s in enumerate(session.started)]


def test_steps_start_at_their_deadlines_and_every_row_is_handed_on() -> None:
    clock = FakeClock()
    session = FakeSession(clock, h=0.001, end=3.0)  # 1 kHz for 1 s
    jitter, rows, start = paced(session, clock)
    assert len(rows) == len(session.started) == 1000
    assert [r[0] for r in rows] == pytest.approx([2.0 + k * 0.001 for k in range(1, 1001)])
    late = offsets(session, start, 1 * MS)
    assert min(late) >= 0 and max(late) <= 5 * TICK  # the spin ends at the deadline
    assert jitter.steps == 1000 and jitter.late == 0
    assert jitter.p99 <= 0.001 and jitter.max <= 0.001
    # It slept most of each period and spun only the last SPIN_NS: each sleep was to wake
    # SPIN_NS before a deadline.
    assert len(clock.sleeps) == 1000  # not before the first step; the last: for the end
    for when, seconds in clock.sleeps:
        assert (when + round(seconds * 1e9) - start - TICK) % MS == pytest.approx(
            MS - SPIN_NS, abs=2
        )


@pytest.mark.parametrize("factor", [2.0, 0.5])
def test_the_factor_scales_the_wall_time_of_a_step(factor: float) -> None:
    clock = FakeClock()
    session = FakeSession(clock, h=0.01, end=2.5)
    jitter, rows, start = paced(session, clock, factor)
    assert len(rows) == 50
    late = offsets(session, start, 10 * MS / factor)
    assert min(late) >= 0 and max(late) <= 5 * TICK
    assert jitter.late == 0


def test_no_drift_when_steps_cost_unevenly_and_sleeps_wake_late() -> None:
    # Sleeps overshoot by 150 us (less than the spin), steps cost 0 to 0.9 of a period:
    # deadlines are absolute, so step 2000 starts as exactly as step 1.
    clock = FakeClock(oversleep_ns=150_000)
    session = FakeSession(clock, h=0.001, end=4.0)
    rng = np.random.default_rng(17)
    session.costs = {k: int(c) for k, c in enumerate(rng.integers(0, 900_000, 2001), start=1)}
    jitter, rows, start = paced(session, clock)
    assert len(rows) == 2000
    late = offsets(session, start, 1 * MS)
    assert min(late) >= 0 and max(late) <= 5 * TICK
    assert jitter.late == 0


def test_a_late_run_starts_steps_at_once_and_counts_each_late_one() -> None:
    clock = FakeClock()
    session = FakeSession(clock, h=0.001, end=2.02)
    session.costs = {5: int(5.5 * MS)}  # step 5 (from t = 2.004) takes 5.5 periods
    jitter, rows, start = paced(session, clock)
    assert len(rows) == 20
    late = offsets(session, start, 1 * MS)
    # Steps 6 to 10 had missed their deadlines when their turn came: each started at once
    # (no sleep between them), as late as it was, not pushed to a new schedule...
    sleeps_while_behind = [
        w for w, _ in clock.sleeps if session.started[5] <= w < session.started[9]
    ]
    assert not sleeps_while_behind
    assert late[5] == pytest.approx(4.5 * MS, abs=5 * TICK)
    assert all(late[k] > late[k + 1] > 0 for k in range(5, 9))
    # ...and from step 11 the run is on its deadlines again.
    assert all(0 <= x <= 5 * TICK for x in late[10:])
    assert jitter.late == 5
    assert jitter.max == pytest.approx(4.5, abs=0.001)
    assert jitter.p50 <= 0.001


def test_oversleeping_past_the_spin_is_late_but_not_behind() -> None:
    clock = FakeClock(oversleep_ns=SPIN_NS + 300_000)  # a kernel waking it 300 us too late
    session = FakeSession(clock, h=0.001, end=2.1)
    jitter, _, start = paced(session, clock)
    late = offsets(session, start, 1 * MS)
    assert all(x == pytest.approx(300_000, abs=3 * TICK) for x in late[1:])
    assert jitter.late == 0  # it did wait: it was not behind
    assert jitter.p99 == pytest.approx(0.3)


def test_a_stop_set_during_a_step_ends_the_run_after_it() -> None:
    clock = FakeClock()
    session = FakeSession(clock, h=0.001, end=100.0)
    stop = threading.Event()
    session.on_step[7] = stop
    jitter, rows, _ = paced(session, clock, stop=stop)
    assert len(rows) == 7 and session.k == 7
    assert jitter.steps == 7


def test_a_stop_ends_a_long_wait_without_another_step() -> None:
    # 1 s steps at 1/1000 of real time: 1000 s between steps, slept in short pieces.
    clock = FakeClock()
    session = FakeSession(clock, h=1.0, end=10.0)
    stop = threading.Event()
    slept: list[float] = []

    def sleep(seconds: float) -> None:
        slept.append(seconds)
        clock.sleep(seconds)
        if len(slept) == 30:
            stop.set()

    jitter = run_paced(session, 0.001, stop, lambda row: None, clock=clock, sleep=sleep)
    assert session.k == 1  # the first step runs at once; the second never came
    assert len(slept) == 30 and max(slept) <= LONG_SLEEP_S
    assert jitter.steps == 1


def test_a_session_already_at_its_end_steps_nothing() -> None:
    clock = FakeClock()
    session = FakeSession(clock, h=0.001, end=2.0)
    jitter, rows, _ = paced(session, clock)
    assert rows == [] and jitter == Jitter(0, 0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("factor", [0.0, -1.0, float("inf"), float("nan")])
def test_a_factor_that_is_not_a_positive_number_is_refused(factor: float) -> None:
    clock = FakeClock()
    with pytest.raises(ValueError, match="real-time factor must be a positive number"):
        run_paced(FakeSession(clock, 0.001, 3.0), factor, threading.Event(), lambda r: None)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="timer slack is Linux's")
def test_the_timer_slack_is_fine_while_pacing_and_given_back_after() -> None:
    prctl = ctypes.CDLL(None, use_errno=True).prctl
    before = prctl(30, 0, 0, 0, 0)  # PR_GET_TIMERSLACK
    clock = FakeClock()
    session = FakeSession(clock, h=0.001, end=2.003)
    seen: list[int] = []
    run_paced(
        session, 1.0, threading.Event(), lambda row: seen.append(prctl(30, 0, 0, 0, 0)),
        clock=clock, sleep=clock.sleep,
    )  # fmt: skip
    assert seen == [1000, 1000, 1000]  # ns
    assert prctl(30, 0, 0, 0, 0) == before


def test_lateness_percentiles_by_nearest_rank() -> None:
    lateness = Lateness()
    for us in range(1, 1001):  # 1 us to 1 ms, one each
        lateness.add(us * 1000, late=False)
    jitter = lateness.jitter()
    assert (jitter.steps, jitter.late) == (1000, 0)
    assert jitter.p50 == 0.5 and jitter.p99 == 0.99 and jitter.max == 1.0


def test_lateness_beyond_10_ms_is_kept_to_the_ms_and_the_max_exact() -> None:
    lateness = Lateness()
    for _ in range(98):
        lateness.add(20_000, late=False)  # 20 us
    lateness.add(123_456_789, late=True)  # 123.456789 ms
    lateness.add(12_000_000_000, late=True)  # 12 s, past the last bin
    jitter = lateness.jitter()
    assert jitter.p50 == 0.02
    assert jitter.p99 == 123.0
    assert lateness.percentile(100) == 12_000.0
    assert jitter.max == 12_000.0 and jitter.late == 2
    assert "2 late (the run was behind)" in str(jitter)
