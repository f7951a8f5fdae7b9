"""How a co-simulation step that does not reach its end goes on (FMI 2.0.4 section 4.2.2,
FMI 3.0 section 4.2.4): a discarded step is retried from the FMU's last successful time (in
halves when it got nowhere), an early return goes on from lastSuccessfulTime, a terminating
FMU ends with Terminated at its end time, and an error is a failure."""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import pytest

from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.blueprints._fmu_cs import DISCARD_RETRIES, CoSimulation
from twinlink.processors.blueprints._fmu_fmi import (
    DISCARD,
    EARLY_RETURN,
    ERROR,
    TERMINATE,
    FmiApi,
    FmuLog,
    Terminated,
)

OK = 0
# A scripted FMU: given (t, h), the status (as FmiApi.do_step gives it), whether it
# terminated, and its last successful time.
Script = Callable[[float, float], tuple[int, bool, float]]


class FakeApi(FmiApi):
    def __init__(self, script: Script) -> None:
        self.script = script
        self.steps: list[tuple[float, float]] = []
        self._outcome: tuple[int, bool, float] = (OK, False, 0.0)

    def accessor(self, op: str, type_: str, vrs: list[int]) -> Callable[[int], int]:
        return lambda at: OK

    def do_step(self, t: float, h: float) -> int:
        self.steps.append((t, h))
        self._outcome = self.script(t, h)
        return self._outcome[0]

    def discarded(self, t: float) -> tuple[bool, float]:
        return self._outcome[1], self._outcome[2]


def engine(script: Script) -> tuple[CoSimulation, FakeApi]:
    api = FakeApi(script)
    fmu: Any = None
    return CoSimulation(fmu, api, FmuLog("off", logging.getLogger("test")), []), api


def test_a_step_discarded_without_termination_is_retried_in_halves() -> None:
    # Steps longer than 0.3 s are discarded with nothing done (lastSuccessfulTime = t).
    cs, api = engine(lambda t, h: (DISCARD, False, t) if h > 0.3 else (OK, False, 0))
    cs.advance(1.0)
    assert cs.time == 1.0
    assert api.steps[:3] == [(0.0, 1.0), (0.0, 0.5), (0.0, 0.25)]
    assert sum(h for t, h in api.steps[2:]) == pytest.approx(1.0)


def test_a_partly_done_step_goes_on_from_the_last_successful_time() -> None:
    # The first step gets to 0.4 s of 1 s and is discarded; the rest is then done.
    cs, api = engine(lambda t, h: (DISCARD, False, 0.4) if t == 0 else (OK, False, 0))
    cs.advance(1.0)
    assert cs.time == 1.0 and api.steps == [(0.0, 1.0), (0.4, pytest.approx(0.6))]


def test_an_early_return_goes_on_from_last_successful_time() -> None:
    cs, api = engine(lambda t, h: (EARLY_RETURN, False, 0.25) if t == 0 else (OK, False, 0))
    cs.advance(1.0)
    assert cs.time == 1.0 and api.steps == [(0.0, 1.0), (0.25, 0.75)]


@pytest.mark.parametrize(
    "outcome",
    [(DISCARD, True, 0.7), (TERMINATE, True, 0.7), (DISCARD, True, 0.0)],
)
def test_a_terminating_fmu_ends_at_its_last_successful_time(
    outcome: tuple[int, bool, float],
) -> None:
    cs, _ = engine(lambda t, h: outcome)
    with pytest.raises(Terminated) as ended:
        cs.advance(1.0)
    assert ended.value.time == cs.time == outcome[2]


def test_a_step_discarded_for_ever_is_a_failure_not_a_loop() -> None:
    cs, api = engine(lambda t, h: (DISCARD, False, t))
    with pytest.raises(BlueprintError, match="keeps discarding"):
        cs.advance(1.0)
    assert len(api.steps) == DISCARD_RETRIES + 1


def test_an_error_is_a_failure() -> None:
    cs, _ = engine(lambda t, h: (ERROR, False, t))
    with pytest.raises(BlueprintError, match="fmi2DoStep returned error"):
        cs.advance(1.0)
