"""The properties of one device: reported values (from the device), desired values (from
people), the version of the desired set, and the delta between them. Stored by a
`PropertyStore` (store/commands.py)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from twinlink.domain.doctime import human_time

Timed = tuple[Any, int]  # a value and when it was set, ns


@dataclass(slots=True)
class DeviceProperties:
    device_id: int
    twin_id: int
    device_created_ns: int
    version: int = 0
    reported: dict[str, Timed] = field(default_factory=dict)
    desired: dict[str, Timed] = field(default_factory=dict)

    def delta(self) -> dict[str, Any]:
        """The desired values the device has not reported (yet)."""
        out = {}
        for name, (value, _) in self.desired.items():
            known = self.reported.get(name)
            if known is None or not same_value(known[0], value):
                out[name] = value
        return out

    def set_desired(self, changes: dict[str, Any], now_ns: int) -> list[str]:
        """Apply a merge patch (None removes); the names that changed. The version goes up
        when anything did."""
        changed = []
        for name, value in changes.items():
            old = self.desired.get(name)
            if value is None:
                if old is not None:
                    del self.desired[name]
                    changed.append(name)
            elif old is None or type(old[0]) is not type(value) or old[0] != value:
                self.desired[name] = (value, now_ns)
                changed.append(name)
        if changed:
            self.version += 1
        return changed

    def set_reported(self, values: dict[str, Any], now_ns: int) -> list[str]:
        for name, value in values.items():
            self.reported[name] = (value, now_ns)
        return list(values)

    def view(self) -> dict[str, Any]:
        return {
            "reported": {n: _timed(v) for n, v in sorted(self.reported.items())},
            "desired": {n: _timed(v) for n, v in sorted(self.desired.items())},
            "delta": self.delta(),
            "version": self.version,
        }


def _timed(value: Timed) -> dict[str, Any]:
    return {"value": value[0], "time": human_time(value[1])}


def same_value(a: Any, b: Any) -> bool:
    """Equal as JSON values: 1 and 1.0 are the same number, but True is not 1."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a == b
    return type(a) is type(b) and bool(a == b)
