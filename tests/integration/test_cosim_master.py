"""The fixed-step co-simulation masters on real FMUs: the mass-spring-damper pair split into
two C FMUs (tests/fmus/msd_mass, msd_spring) against the same system solved as one ODE,
the CSV, parameters, an FMI 3 FMU that terminates, and FMUs that fail."""

from __future__ import annotations

import csv
import io
import math
import tempfile
import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tests.conftest import ROOT, FmuFiles
from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.runner import CosimRunError, Result, run
from twinlink.domain.errors import InvalidInputError

pytestmark = pytest.mark.integration

MASS = Instance("msd1.m1", "msd1.fmu")
SPRING = Instance("msd2.m2", "msd2.fmu")
# Not symmetric, lightly damped, coupled more stiffly than tied to the walls. The INTO-CPS
# example's names: c springs, d dampers, cc and dc the coupling's.
PARAMS = {"m1": 1.0, "c1": 1.0, "d1": 0.1, "m2": 2.0, "c2": 3.0, "d2": 0.05, "cc": 2.0, "dc": 0.2}
X1_0, END = 1.0, 10.0


def _p(instance: Instance, variable: str) -> Port:
    return Port(instance.name, variable)


def msd_system(master: str, step: float, **params: float) -> System:
    values = PARAMS | params
    parameters: dict[Port, float | int | bool | str] = {
        _p(MASS, "x1"): X1_0,
        **{_p(MASS, n): values[n] for n in ("m1", "c1", "d1")},
        **{_p(SPRING, n): values[n] for n in ("m2", "c2", "d2", "cc", "dc")},
    }
    return System(
        instances=(MASS, SPRING),
        connections=(
            Connection(_p(MASS, "x1"), _p(SPRING, "x1")),
            Connection(_p(MASS, "v1"), _p(SPRING, "v1")),
            Connection(_p(SPRING, "fk"), _p(MASS, "fk")),
        ),
        parameters=parameters,
        log_variables={MASS.name: ("x1", "v1"), SPRING.name: ("x2", "fk")},
        algorithm=Algorithm("fixed-step", step, master=master),  # type: ignore[arg-type]
        end_time=END,
        source="maestro",
    )


@pytest.fixture(scope="module")
def msd(fmu_files: FmuFiles) -> dict[str, Path]:
    return {"msd1.fmu": fmu_files("msd_mass"), "msd2.fmu": fmu_files("msd_spring")}


def monolithic(times: np.ndarray, **params: float) -> np.ndarray:
    """x1 and x2 of the same two masses solved as one ODE, tightly."""
    p = PARAMS | params

    def f(_t: float, y: np.ndarray) -> list[float]:
        x1, v1, x2, v2 = y
        fk = p["cc"] * (x2 - x1) + p["dc"] * (v2 - v1)
        a1 = (fk - p["c1"] * x1 - p["d1"] * v1) / p["m1"]
        a2 = (-fk - p["c2"] * x2 - p["d2"] * v2) / p["m2"]
        return [v1, a1, v2, a2]

    sol = solve_ivp(f, (0.0, END), [X1_0, 0.0, 0.0, 0.0], t_eval=times, rtol=1e-11, atol=1e-12)
    assert sol.success
    return np.vstack([sol.y[0], sol.y[2]])


def error(result: Result) -> float:
    """The largest deviation of either position from the monolithic solution."""
    times = result.column("time")
    reference = monolithic(times)
    x1, x2 = result.column("{msd1}.m1.x1"), result.column("{msd2}.m2.x2")
    return float(max(np.max(np.abs(x1 - reference[0])), np.max(np.abs(x2 - reference[1]))))


def test_the_coupled_pair_converges_to_the_monolithic_solution(msd: dict[str, Path]) -> None:
    errors = {
        (master, h): error(run(msd_system(master, h), msd))
        for master in ("jacobi", "gauss-seidel")
        for h in (0.04, 0.02, 0.01)
    }
    for master in ("jacobi", "gauss-seidel"):
        e = [errors[master, h] for h in (0.04, 0.02, 0.01)]
        # first order in the step (inputs held over a step): halving it about halves the error
        assert e[0] > e[1] > e[2]
        assert 1.6 < e[0] / e[1] < 2.5 and 1.6 < e[1] / e[2] < 2.5, (master, e)
        assert e[2] < 0.05, (master, e)
    for h in (0.04, 0.02, 0.01):  # Gauss-Seidel uses this step's x1, v1: closer
        assert errors["gauss-seidel", h] < errors["jacobi", h]


def test_a_changed_mass_changes_the_period(msd: dict[str, Path]) -> None:
    """A lone undamped mass (cc = 0 decouples it): the period is 2 pi sqrt(m1 / c1)."""

    def period(m1: float) -> float:
        system = msd_system("gauss-seidel", 0.001, m1=m1, d1=0.0, cc=0.0, dc=0.0)
        result = run(replace(system, end_time=20.0), msd)
        t, x = result.column("time"), result.column("{msd1}.m1.x1")
        down = np.nonzero((x[:-1] > 0) & (x[1:] <= 0))[0]  # downward zero crossings
        assert len(down) >= 2, f"m1 = {m1}: fewer than two periods in 20 s"
        return float(t[down[1]] - t[down[0]])

    assert period(1.0) == pytest.approx(2 * math.pi, abs=0.002)
    assert period(2.0) == pytest.approx(2 * math.pi * math.sqrt(2.0), abs=0.002)


def test_the_csv_has_maestros_header_and_a_row_per_step(
    msd: dict[str, Path], tmp_path: Path
) -> None:
    fractions: list[float] = []
    result = run(msd_system("gauss-seidel", 0.5), msd, progress=fractions.append)
    out = io.StringIO()
    result.write_csv(out)
    rows = list(csv.reader(io.StringIO(out.getvalue())))
    assert rows[0] == ["time", "{msd1}.m1.x1", "{msd1}.m1.v1", "{msd2}.m2.x2", "{msd2}.m2.fk"]
    assert [float(r[0]) for r in rows[1:]] == [k * 0.5 for k in range(21)]
    assert rows[1][1:3] == [repr(X1_0), "0.0"]  # the start values, before the first step
    assert np.array_equal(np.array(rows[1:], dtype=float), result.values)  # exact round trip
    # fk is computed from the connected x1 at the start: cc (x2 - x1) = 2 (0 - 1)
    assert float(rows[1][4]) == PARAMS["cc"] * (0.0 - X1_0)
    assert fractions == sorted(fractions) and fractions[-1] == 1.0 and len(fractions) <= 101
    assert result.ended == ""
    result.write_csv(tmp_path / "outputs.csv")  # Maestro's file name
    assert (tmp_path / "outputs.csv").read_text(encoding="utf-8") == out.getvalue()


def test_a_stop_ends_the_run_between_steps_with_the_rows_so_far(msd: dict[str, Path]) -> None:
    stop = threading.Event()

    def progress(fraction: float) -> None:
        if fraction >= 0.25:
            stop.set()

    result = run(msd_system("jacobi", 0.01), msd, progress=progress, stop=stop)
    rows = len(result.values)
    assert 0.25 * 1000 < rows < 1001 and result.ended.startswith("stopped at t = ")
    assert not np.isnan(result.values).any()


def test_an_fmi3_fmu_that_terminates_ends_the_run_with_its_rows(fmu_files: FmuFiles) -> None:
    """The FMI 3 Stair (Reference-FMUs) asks to terminate at t = 9 s: the run ends there,
    naming it, with the rows recorded up to and including the terminating step (as the FMU
    blueprint does)."""
    system = System(
        instances=(Instance("stair", "Stair.fmu"),),
        connections=(),
        parameters={},
        log_variables={"stair": ("counter",)},
        algorithm=Algorithm("fixed-step", 0.5),
        end_time=20.0,
        source="yaml",
    )
    result = run(system, {"Stair.fmu": fmu_files("stair3")})
    assert result.columns == ("time", "stair.counter")
    assert "instance 'stair'" in result.ended and "terminate" in result.ended
    times, counter = result.column("time"), result.column("stair.counter")
    assert times[-1] == 9.0 and times[-2] == 8.5 and times[0] == 0.0
    assert counter[0] == 1.0 and counter[-2] == 9.0 and counter[-1] == 10.0


def test_an_fmu_that_fails_to_instantiate_is_named_and_nothing_is_left(
    msd: dict[str, Path], fmu_files: FmuFiles, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The status FMU refuses instances named refuse*, saying why only in its log."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    base = msd_system("gauss-seidel", 0.1)
    refused = Instance("refuse1", "status.fmu")
    system = System(
        instances=(*base.instances, refused),
        connections=(*base.connections, Connection(_p(MASS, "x1"), _p(refused, "u"))),
        parameters=base.parameters,
        log_variables=base.log_variables,
        algorithm=base.algorithm,
        end_time=1.0,
    )
    with pytest.raises(CosimRunError, match=r"instance 'refuse1' \(.*status.*\.fmu\)") as err:
        run(system, {**msd, "status.fmu": fmu_files("status")})
    assert "cannot import module 'twinlink_missing_module'" in str(err.value)
    assert list(tmp_path.iterdir()) == []  # the extracted FMUs are gone
    maps = Path("/proc/self/maps").read_text()
    assert str(tmp_path) not in maps  # and their libraries unloaded (msd1 and msd2 freed)


def test_an_fmu_error_in_a_step_is_named_with_its_message(
    msd: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with pytest.raises(CosimRunError) as err:
        run(msd_system("jacobi", 0.1, m1=0.0), msd)
    message = str(err.value)
    assert "instance 'msd1.m1'" in message and "fmi2DoStep returned error at t = 0" in message
    assert "the mass m1 must be positive, not 0" in message
    assert (
        list(tmp_path.iterdir()) == [] and str(tmp_path) not in Path("/proc/self/maps").read_text()
    )


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"end_time": None}, "needs an end time"),
        (
            {"algorithm": Algorithm("var-step", 0.1, 0.5, 1.0)},
            r"a var-step algorithm needs 0 < min_size \(0.5\) <= size \(0.1\)",
        ),
        ({"algorithm": Algorithm("fixed-step", 0.0)}, "step size must be positive"),
        ({"log_variables": {"msd3.m3": ("x",)}}, "names no instance"),
    ],
)
def test_a_system_the_master_cannot_run_is_refused_before_any_fmu_is_loaded(
    msd: dict[str, Path], change: dict[str, object], message: str
) -> None:
    with pytest.raises(InvalidInputError, match=message):
        run(replace(msd_system("jacobi", 0.1), **change), msd)  # type: ignore[arg-type]


def test_an_unknown_variable_is_named(msd: dict[str, Path]) -> None:
    system = msd_system("jacobi", 0.1)
    bad = replace(system, log_variables={MASS.name: ("x9",)})
    with pytest.raises(CosimRunError, match=r"instance 'msd1.m1' \(.*\) has no variable 'x9'"):
        run(bad, msd)


def test_maestros_own_multi_model_runs_unchanged(msd: dict[str, Path]) -> None:
    """The INTO-CPS mass-spring-damper multi-model in Maestro 2's one-file shape
    (tests/cosim_files/msd), read by the Maestro reader and run on our pair of FMUs."""
    system = read_maestro(ROOT / "tests" / "cosim_files" / "msd" / "maestro2.json")
    paths = {"MassSpringDamper1.fmu": msd["msd1.fmu"], "MassSpringDamper2.fmu": msd["msd2.fmu"]}
    result = run(system, paths)
    assert result.columns == ("time", "{msd2}.msd2i.x2", "{msd2}.msd2i.v2")
    assert result.column("time")[-1] == system.end_time
    # the file's parameters, the first FMU's own start values (m1 = c1 = 1, d1 = 0, x1 = 1)
    params = {"m1": 1.0, "c1": 1.0, "d1": 0.0, "m2": 1.0, "c2": 1.0, "d2": 1.0}
    reference = monolithic(result.column("time"), **params, cc=1.0, dc=1.0)
    assert np.max(np.abs(result.column("{msd2}.msd2i.x2") - reference[1])) < 0.005
