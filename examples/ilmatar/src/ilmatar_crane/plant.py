"""The simulated Ilmatar crane: three travel axes, a hook with a load cell, and the hook's sway.

Pure logic with no clock of its own: whoever owns the plant calls `step(dt)` (the runner does so
at 10 Hz), so tests drive it with exact time steps. Axes follow signed speed set-points through
acceleration ramps and brake in time to stop at their end limits, as a crane's slow-down limit
switches make them do. Coordinates: x along the runway (bridge), y along the girder (trolley),
z up (the hoist gives the hook's height above the floor).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

GRAVITY = 9.81  # m/s^2
GIRDER_HEIGHT = 9.5  # m: rope suspension point above the floor, sets the pendulum length
FLOOR = 0.05  # m: the hook counts as set down below this height
# What the hook picks up each time it is lowered empty to the floor, in turn (kg); the crane's
# rated capacity is 3 200 kg.
PAYLOADS = (450.0, 1200.0, 800.0, 2300.0)


@dataclass(frozen=True)
class AxisLimits:
    low: float  # m
    high: float  # m
    max_speed: float  # m/s, in either direction
    acceleration: float  # m/s^2, used to speed up and to brake


AXIS_LIMITS = {
    "bridge": AxisLimits(low=0.0, high=30.0, max_speed=0.5, acceleration=0.25),
    "trolley": AxisLimits(low=0.0, high=10.0, max_speed=0.4, acceleration=0.25),
    "hoist": AxisLimits(low=0.0, high=8.0, max_speed=0.15, acceleration=0.1),
}
AXES = tuple(AXIS_LIMITS)


@dataclass
class Axis:
    name: str
    limits: AxisLimits
    position: float  # m
    speed: float = 0.0  # m/s, signed
    setpoint: float = 0.0  # m/s, signed: the speed the drive ramps towards
    distance: float = 0.0  # m driven in total, either direction
    acceleration: float = 0.0  # m/s^2 during the last step

    def step(self, dt: float) -> None:
        lim = self.limits
        target = self.setpoint
        # Brake early enough to stand still exactly at an end limit.
        room = lim.high - self.position if target > 0 else self.position - lim.low
        braking = self.speed**2 / (2 * lim.acceleration)
        if target != 0 and room <= braking + abs(self.speed) * dt:
            target = 0.0
        change = max(-lim.acceleration * dt, min(lim.acceleration * dt, target - self.speed))
        old_speed, self.speed = self.speed, self.speed + change
        moved = (old_speed + self.speed) / 2 * dt
        new_position = min(lim.high, max(lim.low, self.position + moved))
        if new_position != self.position + moved:
            self.speed = 0.0  # the end buffer stops the axis
        self.distance += abs(new_position - self.position)
        self.position = new_position
        self.acceleration = (self.speed - old_speed) / dt


@dataclass
class Sway:
    """The hook as a damped pendulum on one horizontal axis; gives the accelerometer's swing."""

    angle: float = 0.0  # rad
    rate: float = 0.0  # rad/s
    damping: float = 0.3  # 1/s

    def step(self, dt: float, rope: float, carriage_acceleration: float) -> float:
        """Advance by `dt`; returns the hook's horizontal acceleration (m/s^2)."""
        alpha = (
            -GRAVITY / rope * math.sin(self.angle)
            - carriage_acceleration / rope * math.cos(self.angle)
            - self.damping * self.rate
        )
        self.rate += alpha * dt
        self.angle += self.rate * dt
        return carriage_acceleration + rope * alpha


@dataclass
class CranePlant:
    """The crane's state. Read the attributes; change speeds only through `set_speed_setpoint`."""

    seed: int = 16052
    time: float = 0.0  # s of simulated time
    payload: float = 0.0  # kg actually hanging on the hook
    hook_load: float = 0.0  # kg as the load cell reads it: payload, dynamics and noise
    hook_acceleration: tuple[float, float, float] = (0.0, 0.0, GRAVITY)  # m/s^2, x y z
    last_manual_command: float | None = None  # plant time of the last operator set-point
    axes: dict[str, Axis] = field(init=False)
    _sway: tuple[Sway, Sway] = field(init=False)
    _rng: random.Random = field(init=False)
    _next_payload: int = field(init=False, default=0)

    def __post_init__(self) -> None:
        start = {"bridge": 12.0, "trolley": 4.0, "hoist": 3.0}
        self.axes = {name: Axis(name, lim, start[name]) for name, lim in AXIS_LIMITS.items()}
        self._sway = (Sway(), Sway())
        self._rng = random.Random(self.seed)

    @property
    def bridge(self) -> Axis:
        return self.axes["bridge"]

    @property
    def trolley(self) -> Axis:
        return self.axes["trolley"]

    @property
    def hoist(self) -> Axis:
        return self.axes["hoist"]

    def axis(self, name: str) -> Axis:
        try:
            return self.axes[name]
        except KeyError:
            raise ValueError(f"no axis {name!r}; the axes are {', '.join(AXES)}") from None

    def set_speed_setpoint(self, axis: str, value: float, *, manual: bool = True) -> None:
        """Set an axis's speed set-point (m/s, signed). `manual` marks an operator's command,
        which pauses the autopilot. Raises ValueError for an unknown axis or a bad speed."""
        target = self.axis(axis)
        if not math.isfinite(value) or abs(value) > target.limits.max_speed:
            raise ValueError(
                f"{axis} speed set-point must be between {-target.limits.max_speed} and "
                f"{target.limits.max_speed} m/s, got {value}"
            )
        target.setpoint = float(value)
        if manual:
            self.last_manual_command = self.time

    def step(self, dt: float) -> None:
        if dt <= 0:
            raise ValueError(f"a step must move time forward, got dt={dt}")
        was_on_floor = self.hoist.position <= FLOOR
        for ax in self.axes.values():
            ax.step(dt)
        self.time += dt
        if not was_on_floor and self.hoist.position <= FLOOR:
            self._hook_touched_floor()
        self._update_hook(dt)

    def _hook_touched_floor(self) -> None:
        # Set the load down if there is one, otherwise hook the next one on.
        if self.payload > 0:
            self.payload = 0.0
        else:
            self.payload = PAYLOADS[self._next_payload % len(PAYLOADS)]
            self._next_payload += 1

    def _update_hook(self, dt: float) -> None:
        rope = max(0.5, GIRDER_HEIGHT - self.hoist.position)
        ax = self._sway[0].step(dt, rope, self.bridge.acceleration)
        ay = self._sway[1].step(dt, rope, self.trolley.acceleration)
        az = GRAVITY + self.hoist.acceleration
        noise = self._rng.gauss
        self.hook_acceleration = (ax + noise(0, 0.02), ay + noise(0, 0.02), az + noise(0, 0.02))
        # The load cell feels the payload's inertia too; on the floor the rope is slack.
        dynamic = 0.0 if self.hoist.position <= FLOOR else self.payload * az / GRAVITY
        self.hook_load = max(0.0, dynamic + noise(0, 0.5 + 0.002 * self.payload))

    def snapshot(self) -> dict[str, float]:
        """Every signal by its historian name (see `signals.SIGNALS`)."""
        values = {"hook_load": round(self.hook_load, 1)}
        for name, ax in self.axes.items():
            values[f"{name}_position"] = round(ax.position, 4)
            values[f"{name}_speed"] = round(ax.speed, 4)
            values[f"{name}_speed_setpoint"] = ax.setpoint
            values[f"{name}_distance"] = round(ax.distance, 3)
        return values
