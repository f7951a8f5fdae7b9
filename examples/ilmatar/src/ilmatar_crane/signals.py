"""The crane's signals, named once for every service: the historian's snake_case name, the OPC UA
browse path under the `Ilmatar` object, the unit and whether an operator may write it."""

from __future__ import annotations

from dataclasses import dataclass

from ilmatar_crane.plant import AXES, AXIS_LIMITS


@dataclass(frozen=True)
class Signal:
    name: str  # historian name, e.g. "hoist_position"
    path: str  # OPC UA browse path below the Ilmatar object, e.g. "Hoist.Position"
    unit: str  # UNECE symbol
    description: str
    writable: bool = False
    low: float | None = None  # the range a writable value must stay in
    high: float | None = None


def _axis_signals(axis: str) -> tuple[Signal, ...]:
    title = axis.capitalize()
    limits = AXIS_LIMITS[axis]
    what = {
        "bridge": "bridge position along the runway",
        "trolley": "trolley position along the girder",
        "hoist": "hook height above the floor",
    }[axis]
    return (
        Signal(f"{axis}_position", f"{title}.Position", "m", f"Measured {what}."),
        Signal(f"{axis}_speed", f"{title}.Speed", "m/s", f"Measured {axis} speed, signed."),
        Signal(
            f"{axis}_speed_setpoint",
            f"{title}.SpeedSetpoint",
            "m/s",
            f"Commanded {axis} speed, signed; the drive ramps towards it.",
            writable=True,
            low=-limits.max_speed,
            high=limits.max_speed,
        ),
        Signal(f"{axis}_distance", f"{title}.Distance", "m", f"Distance the {axis} has driven."),
    )


SIGNALS: tuple[Signal, ...] = (
    *(s for axis in AXES for s in _axis_signals(axis)),
    Signal("hook_load", "Hook.Load", "kg", "Load on the hook as the load cell reads it."),
)
BY_NAME = {s.name: s for s in SIGNALS}
BY_PATH = {s.path: s for s in SIGNALS}


def axis_of(signal: Signal) -> str:
    """The plant axis a set-point signal drives ("hoist" for "hoist_speed_setpoint")."""
    return signal.name.split("_", 1)[0]
