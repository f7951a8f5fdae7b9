"""A three-FMU co-simulation after the INTO-CPS Incubator (tests/fmus/incubator_*): the
heated box (plant), its bang-bang controller with hysteresis, and a Kalman filter that
estimates the box's air temperature and the heater's (which nothing measures) from the
measured air temperature and the heater command. Run with Jacobi and with Gauss-Seidel.

The controller and the plant form a cycle (heater_on -> plant, T -> controller); the filter
is fed by both, so Gauss-Seidel steps it last, with the inputs of the step's end: in that
order the controller decides from T at the end of its step and the filter's prediction is
one step ahead of the plant. The checks below say which sample each one saw.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import FmuFiles
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.runner import Result, run
from twinlink.cosim.session import Session

pytestmark = pytest.mark.integration

T_LOW, T_HIGH = 34.0, 36.0
# The plant starts warmer than the room and its heater warmer still; the filter starts from
# its model description's guess, 21 degC for both, 4 and 9 K off.
PLANT_T0, PLANT_TH0 = 25.0, 30.0
STEP, END = 1.0, 3000.0


@pytest.fixture(scope="module")
def incubator(fmu_files: FmuFiles) -> dict[str, Path]:
    return {
        "plant.fmu": fmu_files("incubator_plant"),
        "controller.fmu": fmu_files("incubator_controller"),
        "kalman.fmu": fmu_files("incubator_kalman"),
    }


def incubator_system(master: str) -> System:
    def p(port: str) -> Port:
        instance, variable = port.split(".")
        return Port(instance, variable)

    wires = [
        ("plant.T", "controller.T"),
        ("controller.heater_on", "plant.heater_on"),
        ("plant.T", "kalman.T_measured"),
        ("controller.heater_on", "kalman.heater_on"),
    ]
    return System(
        instances=(
            Instance("plant", "plant.fmu"),
            Instance("controller", "controller.fmu"),
            Instance("kalman", "kalman.fmu"),
        ),
        connections=tuple(Connection(p(a), p(b)) for a, b in wires),
        parameters={
            p("plant.T"): PLANT_T0,
            p("plant.T_heater"): PLANT_TH0,
            p("controller.T_low"): T_LOW,
            p("controller.T_high"): T_HIGH,
        },
        log_variables={
            "plant": ("T", "T_heater"),
            "controller": ("heater_on",),
            "kalman": ("T_est", "T_heater_est"),
        },
        algorithm=Algorithm("fixed-step", STEP, master=master),  # type: ignore[arg-type]
        end_time=END,
        source="yaml",
    )


def _lag(master: str) -> int:
    """How many rows later the sample a Gauss-Seidel follower saw was recorded."""
    return 1 if master == "gauss-seidel" else 0


@pytest.fixture(scope="module", params=["jacobi", "gauss-seidel"])
def result(request: pytest.FixtureRequest, incubator: dict[str, Path]) -> tuple[str, Result]:
    master: str = request.param
    return master, run(incubator_system(master), incubator)


def test_the_three_fmus_run_to_the_end(result: tuple[str, Result]) -> None:
    _, r = result
    assert r.ended == ""
    assert r.columns == (
        "time",
        "plant.T",
        "plant.T_heater",
        "controller.heater_on",
        "kalman.T_est",
        "kalman.T_heater_est",
    )
    times = r.column("time")
    assert times[0] == 0.0 and times[-1] == END and len(times) == END / STEP + 1
    assert not np.isnan(r.values).any()
    assert r.column("plant.T")[0] == PLANT_T0 and r.column("kalman.T_est")[0] == 21.0


def test_the_controller_switches_the_heater_at_its_band(result: tuple[str, Result]) -> None:
    master, r = result
    t, temp, on = r.column("time"), r.column("plant.T"), r.column("controller.heater_on")
    # The rule, step by step: on below T_low, off above T_high, unchanged inside the band,
    # decided from the temperature the controller was given for its step.
    seen = temp[_lag(master) : _lag(master) + len(t) - 1]
    expected = np.where(seen < T_LOW, 1.0, np.where(seen > T_HIGH, 0.0, on[:-1]))
    assert np.array_equal(on[1:], expected)
    switches = np.count_nonzero(np.diff(on))
    assert switches >= 8, f"{master}: the heater switched only {switches} times in {END:g} s"
    # Once warm, the box stays at the band, overshooting by what the heater's own heat
    # capacity holds when it goes off (the Incubator's known overshoot), well under a kelvin.
    warm = t > 1000
    assert T_LOW - 0.6 < temp[warm].min() < T_LOW < T_HIGH < temp[warm].max() < T_HIGH + 0.6
    assert 0.3 < on[warm].mean() < 0.8  # heating about half the time at 35 degC in a 21 degC room


def test_the_filter_tracks_the_box_and_the_unmeasured_heater(result: tuple[str, Result]) -> None:
    master, r = result
    t = r.column("time")
    temp, heater = r.column("plant.T"), r.column("plant.T_heater")
    est, heater_est = r.column("kalman.T_est"), r.column("kalman.T_heater_est")
    # Its prediction for the end of its step; in Gauss-Seidel it was given the plant's
    # values at that end, so it predicts the row after.
    lag = _lag(master)
    n = len(t) - lag
    air_error = np.abs(est[:n] - temp[lag:])
    heater_error = np.abs(heater_est[:n] - heater[lag:])
    assert air_error[0] == pytest.approx(PLANT_T0 - 21.0, abs=0.5)
    assert heater_error[0] == pytest.approx(PLANT_TH0 - 21.0, abs=0.5)
    # Noise-free measurements and the plant's own model: the estimate converges, the
    # heater's too although it is never measured, and stays there through the switching.
    after = t[:n] >= 100
    assert air_error[after].max() < 1e-3 and heater_error[after].max() < 0.01
    later = t[:n] >= 300
    assert air_error[later].max() < 1e-4 and heater_error[later].max() < 1e-3


def test_a_colder_room_from_outside_keeps_the_heater_on_longer(
    incubator: dict[str, Path],
) -> None:
    """The room's temperature as an external input (mode 3, as the cosim processor feeds
    live data): after 1500 s the room drops from 21 to 15 degC. The controller holds the box
    in its band by heating longer, as the heat balance says it must (heater power times its
    share of the time = G_box (35 - T_room), the band's middle on average), and the filter,
    told the same room temperature, keeps tracking."""
    rooms = [Port("plant", "T_room"), Port("kalman", "T_room")]
    system = replace(incubator_system("jacobi"), end_time=None)  # an open end, as live runs
    with Session(system, incubator, external_inputs=rooms) as session:
        session.set_inputs(dict.fromkeys(rooms, 21.0))
        rows = [session.initialize()]
        for k in range(1, 3001):
            if k == 1501:
                session.set_inputs(dict.fromkeys(rooms, 15.0))
            row = session.step()
            assert row is not None
            rows.append(row)
        columns = session.columns
    values = np.vstack(rows)
    t, temp, on, est = (
        values[:, columns.index(c)]
        for c in ("time", "plant.T", "controller.heater_on", "kalman.T_est")
    )
    power, g_box = 12.15 * 1.53, 0.79  # the plant's defaults
    for part, room in (((t > 1000) & (t <= 1500), 21.0), (t > 2000, 15.0)):  # settled
        # a colder room pulls the box further below the band before the heater's warmth,
        # delayed by its own heat capacity, arrives
        assert T_LOW - 1.0 < temp[part].min() < temp[part].max() < T_HIGH + 1.0
        share = g_box * ((T_LOW + T_HIGH) / 2 - room) / power
        assert on[part].mean() == pytest.approx(share, abs=0.08), room
    assert np.abs(est[t > 300] - temp[t > 300]).max() < 1e-3
