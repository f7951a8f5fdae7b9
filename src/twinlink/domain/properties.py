"""The properties of one device: reported values (from the device), desired values (from
people), the version of the desired set, and the delta between them; with their SQL."""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass, field
from typing import Any

import orjson

from twinlink.commands.rules import same_value
from twinlink.registry.build import human_time

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

    def rows(self, names: list[str]) -> list[tuple[Any, ...]]:
        out = []
        for name in names:
            reported, desired = self.reported.get(name), self.desired.get(name)
            out.append((self.device_id, name, *_sql(reported), *_sql(desired)))
        return out


def _timed(value: Timed) -> dict[str, Any]:
    return {"value": value[0], "time": human_time(value[1])}


def _sql(value: Timed | None) -> tuple[str | None, int | None]:
    return (None, None) if value is None else (orjson.dumps(value[0]).decode(), value[1])


# -- SQL (history.db) ------------------------------------------------------------------------


def load_properties(
    device_id: int, twin_id: int, created_ns: int, conn: sqlite3.Connection
) -> DeviceProperties:
    props = DeviceProperties(device_id, twin_id, created_ns)
    row = conn.execute(
        "SELECT device_created_ns, version FROM device_property_versions WHERE device_id = ?",
        (device_id,),
    ).fetchone()
    if row is None or row[0] != created_ns:
        return props  # nothing stored, or rows of a deleted device that had the same id
    props.version = row[1]
    rows = conn.execute(
        "SELECT name, reported, reported_ns, desired, desired_ns FROM device_properties "
        "WHERE device_id = ?",
        (device_id,),
    )
    for name, reported, reported_ns, desired, desired_ns in rows:
        if reported is not None:
            props.reported[name] = (orjson.loads(reported), reported_ns)
        if desired is not None:
            props.desired[name] = (orjson.loads(desired), desired_ns)
    return props


def save_properties(
    props: tuple[int, int, int, int], rows: list[tuple[Any, ...]], conn: sqlite3.Connection
) -> None:
    """`props` is (device id, twin id, device created, version); `rows` from `rows()`."""
    device_id, _, created_ns, _ = props
    old = conn.execute(
        "SELECT device_created_ns FROM device_property_versions WHERE device_id = ?",
        (device_id,),
    ).fetchone()
    if old is not None and old[0] != created_ns:  # a deleted device's rows: start afresh
        conn.execute("DELETE FROM device_properties WHERE device_id = ?", (device_id,))
    conn.execute(
        "INSERT INTO device_property_versions (device_id, twin_id, device_created_ns, version) "
        "VALUES (?, ?, ?, ?) ON CONFLICT (device_id) DO UPDATE SET twin_id = excluded.twin_id, "
        "device_created_ns = excluded.device_created_ns, version = excluded.version",
        props,
    )
    conn.executemany(
        "INSERT INTO device_properties (device_id, name, reported, reported_ns, desired, "
        "desired_ns) VALUES (?, ?, ?, ?, ?, ?) ON CONFLICT (device_id, name) DO UPDATE SET "
        "reported = excluded.reported, reported_ns = excluded.reported_ns, "
        "desired = excluded.desired, desired_ns = excluded.desired_ns",
        rows,
    )


def delete_properties_of(twin_ids: list[int], conn: sqlite3.Connection) -> None:
    for twin_id in twin_ids:
        conn.execute(
            "DELETE FROM device_properties WHERE device_id IN "
            "(SELECT device_id FROM device_property_versions WHERE twin_id = ?)",
            (twin_id,),
        )
        conn.execute("DELETE FROM device_property_versions WHERE twin_id = ?", (twin_id,))
