"""The var-step master: accuracy for fewer steps than a fixed step, rejected steps rolled back
(FMI 2 FMU state), a step an FMU ends early (fmi2Discard; an FMI 3 early return without
termination) redone up to there by all, and without rollback a run that adapts but never
rejects, saying so. Maestro's var-step constraints (zero crossings, bounded differences,
sampling points, FMUs' maximum step sizes) and the tolerance from the file."""

from __future__ import annotations

import json
import logging
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import ROOT, FmuFiles
from tests.integration.test_cosim_master import monolithic, msd_system
from twinlink.cosim import kinds
from twinlink.cosim.model import Algorithm, Constraint, Instance, Port, System
from twinlink.cosim.protocol import SlaveLike
from twinlink.cosim.reading import read_system
from twinlink.cosim.results import Result
from twinlink.cosim.runner import CosimRunError, run
from twinlink.cosim.session import Session

pytestmark = pytest.mark.integration

MSD_FILES = ROOT / "tests" / "cosim_files" / "msd"

# More damped than the fixed-step tests' pair: the motion dies out, and a var-step master
# lengthens its steps as it does, where a fixed step stays as short as the start needs.
DAMPED = {"d1": 1.0, "d2": 1.0}


@pytest.fixture(scope="module")
def fmus(fmu_files: FmuFiles) -> dict[str, Path]:
    return {
        "msd1.fmu": fmu_files("msd_mass"),
        "msd2.fmu": fmu_files("msd_spring"),
        "ticks.fmu": fmu_files("ticks"),
        "maxstep.fmu": fmu_files("maxstep"),
        "ticks3.fmu": fmu_files("ticks3"),
    }


def varstep(system: System, low: float, high: float) -> System:
    algorithm = system.algorithm
    return replace(
        system,
        algorithm=Algorithm("var-step", algorithm.size, low, high, master=algorithm.master),
    )


def simulate(
    system: System, fmus: dict[str, Path], tolerance: float | None
) -> tuple[Result, Session]:
    with Session(system, fmus, tolerance=tolerance) as session:
        rows = [session.initialize()]
        while (row := session.step()) is not None:
            rows.append(row)
    return Result(session.columns, np.vstack(rows), session.ended), session


def error(result: Result, **params: float) -> float:
    times = result.column("time")
    reference = monolithic(times, **params)
    x1, x2 = result.column("{msd1}.m1.x1"), result.column("{msd2}.m2.x2")
    return float(max(np.max(np.abs(x1 - reference[0])), np.max(np.abs(x2 - reference[1]))))


@pytest.mark.parametrize("master", ["gauss-seidel", "jacobi"])
def test_var_step_converges_with_fewer_steps_than_a_fixed_step(
    fmus: dict[str, Path], master: str
) -> None:
    fixed = run(msd_system(master, 0.005, **DAMPED), fmus)
    finer = run(msd_system(master, 0.002, **DAMPED), fmus)
    system = varstep(msd_system(master, 0.01, **DAMPED), 1e-4, 1.0)
    errors, steps = [], []
    for tolerance in (1e-3, 1e-4, 1e-5):
        result, session = simulate(system, fmus, tolerance)
        assert result.column("time")[-1] == system.end_time and session.ended == ""
        errors.append(error(result, **DAMPED))
        steps.append(session.steps)
    assert errors[0] > errors[1] > errors[2] and steps[0] < steps[1] < steps[2]
    # as accurate as a fixed step of 5 ms (2 ms) in less than half (two thirds) its steps
    for k, reference in ((1, fixed), (2, finer)):
        fixed_steps = len(reference.values) - 1
        assert errors[k] <= error(reference, **DAMPED) * 1.1, (errors, steps)
        assert steps[k] < fixed_steps * (0.5 if k == 1 else 0.67), (errors, steps)


def test_rejected_steps_are_rolled_back(fmus: dict[str, Path]) -> None:
    """Steps too long for the tolerance are redone from the saved FMU states: were they not
    restored, each rejected step's motion would be added twice and the result would drift."""
    system = varstep(msd_system("gauss-seidel", 0.05, **DAMPED), 1e-4, 1.0)
    result, session = simulate(system, fmus, 1e-4)
    assert session.varstep is not None and session.varstep.rollback
    assert session.varstep.rejected >= 1 and session.warnings == []
    assert error(result, **DAMPED) < 0.005
    assert np.diff(result.column("time")).max() > 0.1  # longer as the motion died out


def without_rollback(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    """Instance `name` opens as an FMU that does not declare canGetAndSetFMUstate."""
    opened = kinds.open_slave

    def open_slave(instance: Instance, path: Path, workdir: Path) -> SlaveLike:
        slave = opened(instance, path, workdir)
        if instance.name == name:
            slave.can_rollback = False
        return slave

    monkeypatch.setattr("twinlink.cosim.session.open_slave", open_slave)


def test_without_rollback_the_step_adapts_but_none_is_rejected(
    fmus: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    without_rollback(monkeypatch, "msd2.m2")
    system = varstep(msd_system("gauss-seidel", 0.01, **DAMPED), 1e-4, 1.0)
    result, session = simulate(system, fmus, 1e-4)
    assert session.varstep is not None and not session.varstep.rollback
    assert session.varstep.rejected == 0 and session.varstep.forced >= 1
    assert len(session.warnings) == 1
    assert "instance 'msd2.m2'" in session.warnings[0]
    assert "cannot reject" in session.warnings[0]
    assert error(result, **DAMPED) < 0.01
    assert result.column("time")[-1] == system.end_time


def with_ticks(system: System) -> System:
    clock = Instance("clock", "ticks.fmu")
    return replace(
        system,
        instances=(*system.instances, clock),
        parameters={**system.parameters, Port("clock", "period"): 1.5},
        log_variables={**system.log_variables, "clock": ("ticks",)},
    )


def test_a_step_an_fmu_ends_early_is_redone_by_all_up_to_there(fmus: dict[str, Path]) -> None:
    """The ticks FMU discards every step passing a multiple of 1.5 s, stopping there: every
    instance is brought back and steps to that time, so a row falls on each tick."""
    plain = varstep(msd_system("jacobi", 0.05), 0.001, 0.5)
    result, session = simulate(with_ticks(plain), fmus, 1e-3)
    assert session.varstep is not None and session.varstep.shortened >= 6
    times, ticks = result.column("time"), result.column("clock.ticks")
    for k in range(1, 7):  # ticks at 1.5, 3, ..., 9 s
        row = int(np.searchsorted(times, 1.5 * k))
        assert times[row] == pytest.approx(1.5 * k, abs=1e-9) and ticks[row] == k
        assert ticks[row - 1] == k - 1
    assert error(result) < 1.5 * error(simulate(plain, fmus, 1e-3)[0])  # as accurate


def test_a_step_ended_early_without_rollback_fails_naming_the_instance(
    fmus: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    without_rollback(monkeypatch, "msd1.m1")
    system = with_ticks(varstep(msd_system("jacobi", 0.05), 0.001, 0.5))
    with pytest.raises(CosimRunError, match=r"instance 'clock' \(ticks.fmu\) ended the step"):
        simulate(system, fmus, 1e-3)


def test_a_fixed_step_ended_early_is_an_error_pointing_to_var_step(
    fmus: dict[str, Path],
) -> None:
    system = with_ticks(msd_system("jacobi", 0.2))
    with pytest.raises(CosimRunError, match="use the var-step algorithm") as err:
        run(system, fmus)
    assert "instance 'clock' (ticks.fmu) ended the step from t = 1.4 s early" in str(err.value)


def test_an_fmi3_fmu_rolls_back_with_the_others(fmus: dict[str, Path], fmu_files: FmuFiles) -> None:
    """The FMI 3 Stair (counter = 1 + floor(t), terminating at 9 s) has its state saved
    before every step and restored on every rejected one beside the FMI 2 pair (fmi3GetFMUState,
    fmi3SetFMUState, fmi3FreeFMUState: a failing call fails the run); its counter matches
    each row's time, and its termination ends the run at 9 s, that step recorded."""
    system = varstep(msd_system("gauss-seidel", 0.05, **DAMPED), 1e-4, 1.0)
    system = replace(
        system,
        instances=(*system.instances, Instance("stair", "stair3.fmu")),
        log_variables={**system.log_variables, "stair": ("counter",)},
    )
    result, session = simulate(system, {**fmus, "stair3.fmu": fmu_files("stair3")}, 1e-4)
    assert session.varstep is not None and session.varstep.rollback
    assert session.varstep.rejected >= 1
    times, counter = result.column("time"), result.column("stair.counter")
    assert np.array_equal(counter, 1 + np.floor(times + 1e-9))
    assert times[-1] == 9.0 and counter[-1] == 10.0
    assert session.ended.startswith("instance 'stair' (stair3.fmu) asked to terminate at t = 9 s")


def test_maestros_var_step_file_runs_with_its_constraint_applied(
    fmus: dict[str, Path], tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """The INTO-CPS multi-model with the settings of Maestro's own var-step test (size
    [1e-6, 1], initsize 1e-4, a boundeddifference constraint), read by read_system: the
    constraint (a change of at most 1, or 100 %) is applied without a word."""
    model = json.loads((MSD_FILES / "mm.json").read_text())
    settings = json.loads((MSD_FILES / "varstep.json").read_text())
    path = tmp_path / "varstep.json"
    path.write_text(json.dumps(model | settings))
    with caplog.at_level(logging.WARNING, logger="twinlink.cosim"):
        system = read_system(path)
    assert caplog.text == ""
    assert [(c.name, c.kind) for c in system.algorithm.constraints] == [("bd", "boundeddifference")]
    paths = {"MassSpringDamper1.fmu": fmus["msd1.fmu"], "MassSpringDamper2.fmu": fmus["msd2.fmu"]}
    result, session = simulate(system, paths, 1e-4)
    times = result.column("time")
    assert times[0] == 0.0 and times[1] == pytest.approx(1e-4) and times[-1] == 10.0
    assert session.varstep is not None and session.varstep.rollback and session.steps < 5000
    params = {"m1": 1.0, "c1": 1.0, "d1": 0.0, "m2": 1.0, "c2": 1.0, "d2": 1.0}
    reference = monolithic(times, **params, cc=1.0, dc=1.0)
    assert np.max(np.abs(result.column("{msd2}.msd2i.x2") - reference[1])) < 0.005


X1 = Port("msd1.m1", "x1")


def constrained(system: System, *constraints: Constraint, tolerance: float | None = None) -> System:
    """`system` with a var-step algorithm from its step, between 1e-6 and 1 s."""
    algorithm = Algorithm(
        "var-step",
        system.algorithm.size,
        1e-6,
        1.0,
        master=system.algorithm.master,
        tolerance=tolerance,
        constraints=constraints,
    )
    return replace(system, algorithm=algorithm)


def test_zero_crossings_are_hit_within_the_tolerance(fmus: dict[str, Path]) -> None:
    """Every crossing of x1 through zero has a row within 1e-6 of it (of x1's value); without
    the constraint the rows step over the crossings."""
    base = msd_system("gauss-seidel", 0.05)

    def crossings(result: Result) -> tuple[int, list[int]]:
        x = result.column("{msd1}.m1.x1")
        across = np.flatnonzero(x[:-1] * x[1:] < 0)
        missed = [int(i) for i in across if min(abs(x[i]), abs(x[i + 1])) > 1e-6]
        return int(np.count_nonzero(np.abs(x) <= 1e-6)), missed

    plain, _ = simulate(constrained(base), fmus, 1e-3)
    hits, missed = crossings(plain)
    assert hits == 0 and len(missed) >= 3
    zc = Constraint("zc", "zerocrossing", (X1,), abstol=1e-6)
    for order in (1, 2):
        result, session = simulate(constrained(base, replace(zc, order=order)), fmus, 1e-3)
        hits, missed = crossings(result)
        assert missed == [] and hits >= 3, (order, hits, missed)
        assert session.varstep is not None and session.warnings == []
        assert error(result) < 2 * error(plain)  # no less accurate for it


def test_a_bounded_difference_limits_the_change_over_a_step(fmus: dict[str, Path]) -> None:
    base = msd_system("gauss-seidel", 0.05)
    plain, _ = simulate(constrained(base), fmus, 1e-3)
    assert np.max(np.abs(np.diff(plain.column("{msd1}.m1.x1")))) > 0.02
    bd = Constraint("bd", "boundeddifference", (X1,), abstol=0.005, reltol=0.0)
    result, session = simulate(constrained(base, bd), fmus, 1e-3)
    assert np.max(np.abs(np.diff(result.column("{msd1}.m1.x1")))) <= 0.005 * (1 + 1e-9)
    assert session.varstep is not None and session.varstep.forced == 0
    # relative: a change of at most 10 % of the value (or 1e-3 near zero)
    bd = Constraint("bd", "boundeddifference", (X1,), abstol=1e-3, reltol=0.1)
    x = simulate(constrained(base, bd), fmus, 1e-3)[0].column("{msd1}.m1.x1")
    bound = np.maximum(1e-3, 0.1 * np.maximum(np.abs(x[1:]), np.abs(x[:-1])))
    assert np.all(np.abs(np.diff(x)) <= bound * (1 + 1e-9))


def test_every_sampling_point_is_a_row(fmus: dict[str, Path]) -> None:
    """Samples every 0.5 s from 0.3 s: (3 + 5k) 10^-1 s."""
    sr = Constraint("sr", "samplingrate", base=-1, rate=5, start_time=3)
    result, _ = simulate(constrained(msd_system("jacobi", 0.05), sr), fmus, 1e-3)
    times = result.column("time")
    samples = 0.3 + 0.5 * np.arange(20)
    at = np.searchsorted(times, samples - 1e-12)
    assert np.allclose(times[at], samples, rtol=0, atol=1e-12)
    plain, _ = simulate(constrained(msd_system("jacobi", 0.05)), fmus, 1e-3)
    distance = np.abs(plain.column("time")[:, None] - samples[None, :]).min(axis=0)
    assert np.count_nonzero(distance < 1e-12) < 5  # without it, the rows miss them
    assert error(result) < 1.5 * error(plain)


def test_fmus_maximum_step_sizes_are_asked(fmus: dict[str, Path]) -> None:
    """The maxstep FMU says how far its next tick (every 0.7 s) is through fmi2GetMaxStepsize:
    with the fmumaxstepsize constraint no step goes over one; the mass and spring provide no
    such function, which the run says."""
    pair = msd_system("jacobi", 0.05)
    base = replace(
        pair,
        instances=(*pair.instances, Instance("clock", "maxstep.fmu")),
        parameters={**pair.parameters, Port("clock", "period"): 0.7},
        log_variables={**pair.log_variables, "clock": ("missed",)},
    )
    plain, _ = simulate(constrained(base), fmus, 1e-3)
    assert plain.column("clock.missed")[-1] > 0
    fm = Constraint("fm", "fmumaxstepsize")
    result, session = simulate(constrained(base, fm), fmus, 1e-3)
    assert result.column("clock.missed")[-1] == 0
    times = result.column("time")
    ticks = 0.7 * np.arange(1, 15)
    assert np.allclose(times[np.searchsorted(times, ticks - 1e-9)], ticks, rtol=0, atol=1e-9)
    assert session.warnings == [
        "constraint fm (fmumaxstepsize): instance 'msd1.m1' (msd_mass.fmu), instance "
        "'msd2.m2' (msd_spring.fmu) provide no fmi2GetMaxStepsize; only the others are asked"
    ]


def test_the_tolerance_comes_from_the_file_unless_given(fmus: dict[str, Path]) -> None:
    base = msd_system("gauss-seidel", 0.01, **DAMPED)
    _, coarse = simulate(constrained(base, tolerance=1e-3), fmus, None)
    _, fine = simulate(constrained(base, tolerance=1e-5), fmus, None)
    assert fine.steps > 2 * coarse.steps
    _, given = simulate(constrained(base, tolerance=1e-5), fmus, 1e-3)  # the caller's wins
    assert given.steps == coarse.steps
    _, default = simulate(constrained(base), fmus, None)  # varstep.TOLERANCE, 1e-3
    assert default.steps == coarse.steps


def test_without_rollback_a_constraint_only_bounds_the_next_step(
    fmus: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    without_rollback(monkeypatch, "msd2.m2")
    bd = Constraint("bd", "boundeddifference", (X1,), abstol=0.005, reltol=0.0)
    result, session = simulate(constrained(msd_system("gauss-seidel", 0.05), bd), fmus, 1e-3)
    assert session.varstep is not None and session.varstep.rejected == 0
    assert "cannot reject" in session.warnings[0]
    steps = np.abs(np.diff(result.column("{msd1}.m1.x1")))
    assert np.median(steps) <= 0.005  # sized from the last change: most within the bound


def with_ticks3(system: System) -> System:
    return replace(
        system,
        instances=(*system.instances, Instance("clock3", "ticks3.fmu")),
        log_variables={**system.log_variables, "clock3": ("counter",)},
    )


def test_an_fmi3_early_return_without_termination_is_a_row_and_the_run_goes_on(
    fmus: dict[str, Path],
) -> None:
    """The FMI 3 ticks3 FMU returns early from every step passing a whole second
    (earlyReturn, lastSuccessfulTime that second, terminateRequested false): every instance is
    brought back and steps to that second, a row falls on each, and the run reaches its end."""
    result, session = simulate(
        with_ticks3(varstep(msd_system("jacobi", 0.05), 1e-3, 0.5)), fmus, 1e-3
    )
    assert session.ended == "" and session.varstep is not None
    assert session.varstep.shortened >= 9
    times, counter = result.column("time"), result.column("clock3.counter")
    assert times[-1] == 10.0
    assert np.array_equal(counter, 1 + np.floor(times + 1e-9))  # no instance ahead of another
    for second in range(1, 10):
        row = int(np.searchsorted(times, second - 1e-9))
        assert times[row] == pytest.approx(second, abs=1e-9) and counter[row] == second + 1


def test_an_fmi3_early_return_without_rollback_fails_naming_the_instance(
    fmus: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    without_rollback(monkeypatch, "msd1.m1")
    system = with_ticks3(varstep(msd_system("jacobi", 0.05), 1e-3, 0.5))
    with pytest.raises(CosimRunError, match=r"instance 'clock3' \(ticks3.fmu\) ended the step"):
        simulate(system, fmus, 1e-3)
    with pytest.raises(CosimRunError, match="use the var-step algorithm"):
        run(with_ticks3(msd_system("jacobi", 0.3)), fmus)  # 0.9 -> 1.2 s passes 1 s
