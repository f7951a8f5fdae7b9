"""The Tingen cantilever FMUs (FMI 2.0 and 3.0) against beam theory and the exact oscillator.

The reference numbers are computed here from the thesis's values (table 3.1) and the textbook
step response of a damped oscillator, written independently of the C code (which advances a
state-transition form of the same solution).
"""

from __future__ import annotations

import ctypes
import math
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
)
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from tests.conftest import FmuFiles
from tests.integration._fmi2_log import Fmi2Log

pytestmark = pytest.mark.integration

# NTNU thesis, table 3.1
L = 0.300  # m
I = 2.1e-12  # m^4 (2.1 mm^4)  # noqa: E741
E = 210e9  # Pa (210000 N/mm^2)
# The FMU's other defaults
C_FIBER = 0.0005  # m, half of the 1 mm thickness
BEAM_MASS_PER_LENGTH = 0.196  # kg/m
RAYLEIGH = 0.2357

FMUS = ["tingen", "tingen3"]
VR_F, VR_THETA, VR_SIGMA, VR_W = 1, 2, 3, 4
VR_L, VR_ZETA = 10, 15


def stiffness() -> float:
    return 3 * E * I / L**3


def step_response(t: np.ndarray, force: float, tip_mass: float, zeta: float) -> np.ndarray:
    """Tip deflection from rest under `force` applied at t = 0 (textbook step response)."""
    k = stiffness()
    m = tip_mass + RAYLEIGH * BEAM_MASS_PER_LENGTH * L
    wn = math.sqrt(k / m)
    static = force / k
    if zeta < 1:
        wd = wn * math.sqrt(1 - zeta**2)
        decay = np.exp(-zeta * wn * t)
        return static * (
            1 - decay * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta**2) * np.sin(wd * t))
        )
    if zeta == 1:
        return static * (1 - np.exp(-wn * t) * (1 + wn * t))
    root = math.sqrt(zeta**2 - 1)
    r1, r2 = -wn * (zeta - root), -wn * (zeta + root)
    return static * (1 - (r2 * np.exp(r1 * t) - r1 * np.exp(r2 * t)) / (r2 - r1))


def assert_response(
    result: np.ndarray, force: float, tip_mass: float, zeta: float, tol: float
) -> None:
    """w, theta and sigma all follow the exact response; errors relative to the static values."""
    w = step_response(result["time"], force, tip_mass, zeta)
    static_w = force / stiffness()
    expected = {
        "w": w,
        "theta": 3 * w / (2 * L),
        "sigma": stiffness() * w * L * C_FIBER / I,
    }
    for name, values in expected.items():
        scale = values.max() if values.max() > 0 else 3 * static_w / (2 * L)
        error = np.max(np.abs(result[name] - values)) / scale
        assert error < tol, f"{name}: relative error {error:.3g} >= {tol:g}"


def simulate(path: Path, fmi_type: str, **kwargs: object) -> np.ndarray:
    result = fmpy.simulate_fmu(str(path), fmi_type=fmi_type, **kwargs)
    return np.asarray(result)


# --------------------------------------------------------------------------------------------
# Physics
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", FMUS)
def test_a_held_force_settles_at_the_beam_theory_angle_and_stress(
    fmu_files: FmuFiles, name: str
) -> None:
    force = 2.0
    result = simulate(
        fmu_files(name),
        "CoSimulation",
        start_values={"F": force, "zeta": 0.5},
        stop_time=2.0,
        output_interval=0.01,
    )
    theta = force * L**2 / (2 * E * I)  # thesis eq. 4.1, F = 2 E I theta / L^2, inverted
    sigma = force * L * C_FIBER / I  # M c / I with the root moment M = F L
    assert result["theta"][-1] == pytest.approx(theta, rel=1e-6)
    assert result["sigma"][-1] == pytest.approx(sigma, rel=1e-6)
    assert result["w"][-1] == pytest.approx(force / stiffness(), rel=1e-6)
    assert theta == pytest.approx(0.2041, abs=1e-4)  # the numbers themselves: 11.7 degrees
    assert sigma == pytest.approx(142.86e6, rel=1e-4)  # and 143 MPa


@pytest.mark.parametrize("step", [0.001, 0.01, 0.1])
@pytest.mark.parametrize("name", FMUS)
def test_co_simulation_is_exact_at_any_step_size(
    fmu_files: FmuFiles, name: str, step: float
) -> None:
    result = simulate(
        fmu_files(name),
        "CoSimulation",
        start_values={"F": 2.0, "tip_mass": 0.5, "zeta": 0.02},
        stop_time=2.0,
        output_interval=step,
    )
    n = round(2.0 / step)
    assert len(result) == n + 1
    np.testing.assert_allclose(result["time"], np.arange(n + 1) * step, rtol=1e-12, atol=1e-12)
    assert_response(result, 2.0, 0.5, 0.02, tol=1e-9)


@pytest.mark.parametrize(
    ("zeta", "step"),
    [
        (0.0, 0.01),  # undamped
        (0.0, 0.5),
        (1.0, 0.01),  # critically damped
        (1.0, 0.5),
        (5.0, 0.01),  # over-damped
        (5.0, 0.5),  # over-damped with d * h > 20: the overflow-safe branch
    ],
)
def test_co_simulation_is_exact_for_every_damping_regime(
    fmu_files: FmuFiles, zeta: float, step: float
) -> None:
    result = simulate(
        fmu_files("tingen"),
        "CoSimulation",
        start_values={"F": -3.0, "tip_mass": 0.5, "zeta": zeta},
        stop_time=5.0,
        output_interval=step,
    )
    assert len(result) == round(5.0 / step) + 1
    w = step_response(result["time"], -3.0, 0.5, zeta)
    error = np.max(np.abs(result["w"] - w)) / (3.0 / stiffness())
    assert error < 1e-9


@pytest.mark.parametrize("name", FMUS)
def test_model_exchange_with_cvode_follows_the_exact_response(
    fmu_files: FmuFiles, name: str
) -> None:
    result = simulate(
        fmu_files(name),
        "ModelExchange",
        solver="CVode",
        relative_tolerance=1e-8,
        start_values={"F": 2.0, "tip_mass": 0.5, "zeta": 0.02},
        stop_time=2.0,
        output_interval=0.01,
    )
    assert result["time"][-1] == pytest.approx(2.0)
    assert_response(result, 2.0, 0.5, 0.02, tol=1e-4)


@pytest.mark.parametrize("name", FMUS)
def test_the_fmu_passes_fmpy_validation(fmu_files: FmuFiles, name: str) -> None:
    assert validate_fmu(str(fmu_files(name))) == []
    description = fmpy.read_model_description(str(fmu_files(name)))
    assert description.coSimulation is not None
    assert description.modelExchange is not None
    assert description.defaultExperiment.stopTime == "10"
    assert description.defaultExperiment.stepSize == "0.001"
    variables = {v.name: v for v in description.modelVariables}
    assert {n: variables[n].valueReference for n in ("F", "theta", "sigma", "w")} == {
        "F": VR_F,
        "theta": VR_THETA,
        "sigma": VR_SIGMA,
        "w": VR_W,
    }
    force = variables["F"]
    assert (force.causality, force.unit, force.min, force.max) == ("input", "N", "-50", "50")
    assert [variables[n].unit for n in ("theta", "sigma", "w")] == ["rad", "Pa", "m"]


# --------------------------------------------------------------------------------------------
# The FMI interface: errors are refused and logged
# --------------------------------------------------------------------------------------------


def open_fmi2(path: Path, unzipdir: Path, guid: str | None = None) -> tuple[FMU2Slave, Fmi2Log]:
    description = fmpy.read_model_description(str(path))
    fmu = FMU2Slave(
        guid=guid or description.guid,
        unzipDirectory=fmpy.extract(str(path), unzipdir=str(unzipdir)),
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="tingen-test",
    )
    log = Fmi2Log()
    return fmu, log


def test_fmi2_refuses_bad_calls_with_a_logged_error(fmu_files: FmuFiles, tmp_path: Path) -> None:
    fmu, log = open_fmi2(fmu_files("tingen"), tmp_path / "fmu")
    fmu.instantiate(callbacks=log.callbacks, loggingOn=True)
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()

        with pytest.raises(FMICallException) as caught:
            fmu.getReal([99])
        assert caught.value.status == 3
        assert "unknown value reference 99" in log.text()

        with pytest.raises(FMICallException):
            fmu.setReal([99], [1.0])
        assert "fmi2SetReal: unknown value reference 99" in log.text()

        with pytest.raises(FMICallException):
            fmu.getInteger([1])
        assert "fmi2GetInteger: unknown value reference 1" in log.text()

        with pytest.raises(FMICallException):
            fmu.setReal([VR_L], [0.5])  # a fixed parameter, after initialization
        assert "L is a fixed parameter" in log.text()

        with pytest.raises(FMICallException):
            fmu.setReal([VR_ZETA], [-0.1])
        assert "zeta = -0.1 is not allowed" in log.text()

        with pytest.raises(FMICallException):
            fmu.getFMUstate()
        assert "fmi2GetFMUstate is not supported by this FMU." in log.text()

        # A Model Exchange function on a Co-Simulation instance (FMU2Slave has no wrapper).
        derivatives = (ctypes.c_double * 2)()
        status = fmu.dll.fmi2GetDerivatives(ctypes.c_void_p(fmu.component), derivatives, 2)
        assert status == 3
        assert "fmi2GetDerivatives is only available in Model Exchange." in log.text()

        # zeta is tunable: it may change between steps, and the FMU keeps working.
        fmu.setReal([VR_ZETA, VR_F], [0.3, 1.0])
        fmu.doStep(0.0, 0.5)
        assert fmu.getReal([VR_ZETA]) == [0.3]
        assert all(
            status == 3 and category == "logStatusError" for status, category, _ in log.messages
        )
        assert len(log.messages) == 7
        fmu.terminate()
    finally:
        fmu.freeInstance()


def test_fmi2_refuses_a_wrong_guid(fmu_files: FmuFiles, tmp_path: Path) -> None:
    fmu, log = open_fmi2(fmu_files("tingen"), tmp_path / "fmu", guid="{not-the-guid}")
    with pytest.raises(Exception, match="Failed to instantiate model"):
        fmu.instantiate(callbacks=log.callbacks)
    assert "wrong GUID {not-the-guid}" in log.text()
    fmu.freeLibrary()


def test_fmi3_refuses_an_unknown_value_reference_with_a_logged_error(
    fmu_files: FmuFiles, tmp_path: Path
) -> None:
    path = fmu_files("tingen3")
    description = fmpy.read_model_description(str(path))
    messages: list[tuple[int, str, str]] = []

    def log(env: object, status: int, category: bytes, message: bytes) -> None:
        messages.append((status, category.decode(), message.decode()))

    fmu = FMU3Slave(
        guid=description.guid,
        unzipDirectory=fmpy.extract(str(path), unzipdir=str(tmp_path / "fmu")),
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="tingen3-test",
    )
    fmu.instantiate(loggingOn=True, logMessage=log)
    try:
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()
        with pytest.raises(FMICallException) as caught:
            fmu.getFloat64([99])
        assert caught.value.status == 3
        fmu.setFloat64([VR_F], [2.0])
        fmu.doStep(0.0, 0.25)
        assert fmu.getFloat64([0]) == [0.25]  # time
        w = step_response(np.array([0.25]), 2.0, 0.0, 0.02)[0]
        assert fmu.getFloat64([VR_W])[0] == pytest.approx(w, rel=1e-9)
        fmu.terminate()
    finally:
        fmu.freeInstance()
    assert messages == [(3, "logStatusError", "fmi3GetFloat64: unknown value reference 99.")]
