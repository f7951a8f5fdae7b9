"""A demo operator: drives the crane round a fixed lifting route so the historian, the OPC UA
server and the sensors have something to show. It steps aside for `hold_s` seconds whenever a
person commands a set-point, so manual driving through the bridge is never fought over."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ilmatar_crane.plant import AXES, CranePlant

# Each waypoint moves some axes to target positions (m) at the same time. Lowering the hook to
# the floor picks a load up or sets it down (see CranePlant), so the route alternates the two.
ROUTE: tuple[dict[str, float], ...] = (
    {"hoist": 0.0},
    {"hoist": 5.0},
    {"bridge": 22.0, "trolley": 7.5},
    {"hoist": 0.0},
    {"hoist": 5.0},
    {"bridge": 6.0, "trolley": 2.0},
)
TOLERANCE = 0.03  # m
MIN_SPEED = 0.02  # m/s: below this the drive would creep towards the target for ever
SPEED_FRACTION = 0.8  # of the axis's top speed, as a careful operator would drive


@dataclass
class Autopilot:
    hold_s: float = 120.0
    waypoint: int = 0
    _commanded: dict[str, float] = field(default_factory=dict)  # the set-points it last gave

    def drive(self, plant: CranePlant) -> None:
        """Update the plant's set-points for the next step (call before `plant.step`)."""
        last = plant.last_manual_command
        if last is not None and plant.time - last < self.hold_s:
            self._let_go(plant)
            return
        targets = ROUTE[self.waypoint % len(ROUTE)]
        arrived = True
        for axis in AXES:
            target = targets.get(axis)
            speed = 0.0 if target is None else self._speed_towards(plant, axis, target)
            arrived = arrived and speed == 0.0
            plant.set_speed_setpoint(axis, speed, manual=False)
            self._commanded[axis] = speed
        if arrived:
            self.waypoint = (self.waypoint + 1) % len(ROUTE)

    def _let_go(self, plant: CranePlant) -> None:
        # Stop the axes the autopilot had moving, but leave alone what the operator has set.
        for axis, speed in self._commanded.items():
            if plant.axis(axis).setpoint == speed:
                plant.set_speed_setpoint(axis, 0.0, manual=False)
        self._commanded.clear()

    @staticmethod
    def _speed_towards(plant: CranePlant, axis: str, target: float) -> float:
        ax = plant.axis(axis)
        error = target - ax.position
        if abs(error) <= TOLERANCE:
            return 0.0
        # The speed from which the drive can still brake to a stop at the target.
        braking = math.sqrt(2 * ax.limits.acceleration * abs(error))
        speed = max(MIN_SPEED, min(ax.limits.max_speed * SPEED_FRACTION, 0.7 * braking))
        return math.copysign(speed, error)
