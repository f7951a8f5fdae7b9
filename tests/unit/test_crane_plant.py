"""The simulated crane: speed ramps, end limits, set-points, the hook load and the autopilot."""

from __future__ import annotations

import math

import pytest

from ilmatar_crane.autopilot import ROUTE, Autopilot
from ilmatar_crane.plant import AXES, AXIS_LIMITS, FLOOR, PAYLOADS, CranePlant
from ilmatar_crane.signals import BY_PATH, SIGNALS

DT = 0.1


def run(plant: CranePlant, seconds: float, autopilot: Autopilot | None = None) -> None:
    for _ in range(round(seconds / DT)):
        if autopilot is not None:
            autopilot.drive(plant)
        plant.step(DT)


def test_speed_ramps_to_the_setpoint_at_the_axis_acceleration() -> None:
    plant = CranePlant()
    limits = AXIS_LIMITS["bridge"]
    plant.set_speed_setpoint("bridge", limits.max_speed)
    speeds = []
    for _ in range(30):
        plant.step(DT)
        speeds.append(plant.bridge.speed)
    assert speeds[0] == pytest.approx(limits.acceleration * DT)
    steps = [b - a for a, b in zip([0.0, *speeds], speeds, strict=False)]
    assert all(s <= limits.acceleration * DT + 1e-12 for s in steps)
    assert speeds == sorted(speeds)
    assert speeds[-1] == pytest.approx(limits.max_speed)
    # Reversing ramps down through zero, never jumps.
    plant.set_speed_setpoint("bridge", -limits.max_speed)
    plant.step(DT)
    assert plant.bridge.speed == pytest.approx(limits.max_speed - limits.acceleration * DT)


@pytest.mark.parametrize("axis", AXES)
def test_axes_stop_at_both_end_limits(axis: str) -> None:
    plant = CranePlant()
    limits = AXIS_LIMITS[axis]
    for direction, end in ((1, limits.high), (-1, limits.low)):
        plant.set_speed_setpoint(axis, direction * limits.max_speed)
        positions = []
        for _ in range(round(2 * (limits.high - limits.low) / limits.max_speed / DT)):
            plant.step(DT)
            positions.append(plant.axis(axis).position)
        assert all(limits.low <= p <= limits.high for p in positions)
        assert plant.axis(axis).position == pytest.approx(end, abs=0.01)
        assert plant.axis(axis).speed == pytest.approx(0.0, abs=1e-9)
        # The set-point still asks for more; the axis stays put at the limit.
        plant.step(DT)
        assert plant.axis(axis).position == pytest.approx(end, abs=0.01)


def test_the_axis_brakes_before_the_limit_instead_of_hitting_it() -> None:
    plant = CranePlant()
    plant.set_speed_setpoint("trolley", AXIS_LIMITS["trolley"].max_speed)
    hardest = 0.0
    for _ in range(400):
        plant.step(DT)
        hardest = min(hardest, plant.trolley.acceleration)
    # Braking stays within the drive's ramp: no buffer crash from full speed.
    assert hardest >= -AXIS_LIMITS["trolley"].acceleration - 1e-9


def test_distance_counts_travel_in_both_directions() -> None:
    plant = CranePlant()
    start = highest = plant.hoist.position
    for setpoint in (0.1, -0.1, 0.0):
        plant.set_speed_setpoint("hoist", setpoint)
        for _ in range(100):
            plant.step(DT)
            highest = max(highest, plant.hoist.position)
    up, down = highest - start, highest - plant.hoist.position
    assert up > 0.8 and down > 0.8
    assert plant.hoist.distance == pytest.approx(up + down)


@pytest.mark.parametrize("value", [0.51, -0.6, math.nan, math.inf])
def test_bad_setpoints_are_refused_and_change_nothing(value: float) -> None:
    plant = CranePlant()
    plant.set_speed_setpoint("bridge", 0.2)
    with pytest.raises(ValueError, match="bridge speed set-point"):
        plant.set_speed_setpoint("bridge", value)
    assert plant.bridge.setpoint == 0.2


def test_unknown_axis_and_backwards_time_are_refused() -> None:
    plant = CranePlant()
    with pytest.raises(ValueError, match="no axis 'gantry'"):
        plant.set_speed_setpoint("gantry", 0.1)
    with pytest.raises(ValueError, match="forward"):
        plant.step(0.0)


def test_manual_setpoints_are_stamped_and_autopilot_ones_are_not() -> None:
    plant = CranePlant()
    run(plant, 1)
    plant.set_speed_setpoint("trolley", 0.1, manual=False)
    assert plant.last_manual_command is None
    plant.set_speed_setpoint("trolley", 0.2)
    assert plant.last_manual_command == pytest.approx(1.0)


def test_lowering_to_the_floor_picks_a_load_up_then_sets_it_down() -> None:
    plant = CranePlant()
    assert plant.payload == 0.0
    for expected in (PAYLOADS[0], 0.0, PAYLOADS[1]):
        plant.set_speed_setpoint("hoist", -AXIS_LIMITS["hoist"].max_speed)
        run(plant, 40)
        assert plant.hoist.position <= FLOOR
        assert plant.payload == expected
        plant.set_speed_setpoint("hoist", AXIS_LIMITS["hoist"].max_speed)
        run(plant, 10)
    # Hanging still, the load cell reads the payload give or take its noise.
    plant.set_speed_setpoint("hoist", 0.0)
    run(plant, 5)
    readings = []
    for _ in range(20):
        plant.step(DT)
        readings.append(plant.hook_load)
    assert sum(readings) / len(readings) == pytest.approx(PAYLOADS[1], rel=0.01)
    assert len(set(readings)) > 1  # a real sensor is never perfectly still


def test_accelerating_the_trolley_swings_the_hook() -> None:
    plant = CranePlant()
    still = plant.hook_acceleration
    plant.set_speed_setpoint("trolley", AXIS_LIMITS["trolley"].max_speed)
    run(plant, 1)
    _, y, z = plant.hook_acceleration
    assert abs(y) > 0.1 > abs(still[1])
    assert z == pytest.approx(9.81, abs=0.2)


def test_snapshot_has_every_signal_and_the_same_seed_gives_the_same_run() -> None:
    first, second = CranePlant(seed=7), CranePlant(seed=7)
    for plant in (first, second):
        plant.set_speed_setpoint("hoist", -0.15)
        run(plant, 30)
    assert first.snapshot() == second.snapshot()
    assert set(first.snapshot()) == {s.name for s in SIGNALS}
    assert BY_PATH["Hoist.SpeedSetpoint"].writable
    assert [s.path for s in SIGNALS if s.writable] == [
        "Bridge.SpeedSetpoint",
        "Trolley.SpeedSetpoint",
        "Hoist.SpeedSetpoint",
    ]


def test_autopilot_drives_the_route_and_lifts_loads() -> None:
    plant, pilot = CranePlant(), Autopilot()
    run(plant, 60, pilot)
    assert plant.payload == PAYLOADS[0]  # went down to the floor and hooked a load
    visited = set()
    for _ in range(3000):
        visited.add(pilot.waypoint)
        pilot.drive(plant)
        plant.step(DT)
    assert visited == set(range(len(ROUTE)))
    assert plant.bridge.distance > 10 and plant.trolley.distance > 4


def test_autopilot_steps_aside_for_a_manual_command() -> None:
    plant, pilot = CranePlant(), Autopilot(hold_s=20)
    run(plant, 5, pilot)
    assert plant.hoist.setpoint < 0  # lowering the hook to pick a load up
    plant.set_speed_setpoint("bridge", 0.3)
    run(plant, 19, pilot)
    # The operator's command stands; what the autopilot had moving is stopped.
    assert plant.bridge.setpoint == 0.3
    assert plant.hoist.setpoint == 0.0
    run(plant, 2, pilot)
    assert plant.bridge.setpoint != 0.3  # the hold is over; the autopilot drives again
    assert plant.hoist.setpoint != 0.0
