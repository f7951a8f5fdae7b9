"""Device properties in history.db (`PropertyStore`): one row per device and property, and
the version of each device's desired set. Writes share the history writer's group commits;
reads use a connection of their own (own_reader.py)."""

from __future__ import annotations

import sqlite3
from functools import partial
from typing import Any

import orjson

from twinlink.domain.properties import DeviceProperties, Timed
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.history.own_reader import OwnReader


class SqliteProperties:
    def __init__(self, history: SqliteHistory) -> None:
        self.history = history
        self.reader = OwnReader(history.path, "twinlink-props-read")

    async def open(self) -> None:
        await self.reader.open()

    async def close(self) -> None:
        await self.reader.close()

    async def load_properties(
        self, device_id: int, twin_id: int, created_ns: int
    ) -> DeviceProperties:
        return await self.reader.read(partial(_load, device_id, twin_id, created_ns))

    async def save_properties(self, props: DeviceProperties, names: list[str]) -> None:
        # Taken now: the caller goes on changing `props` while the commit runs.
        key = (props.device_id, props.twin_id, props.device_created_ns, props.version)
        await self.history.write(partial(_save, key, property_rows(props, names)))

    async def delete_properties_of(self, twin_ids: list[int]) -> None:
        await self.history.write(partial(_delete_of, twin_ids))


def property_rows(props: DeviceProperties, names: list[str]) -> list[tuple[Any, ...]]:
    """(device id, name, reported, reported_ns, desired, desired_ns) of each of `names`."""
    out = []
    for name in names:
        reported, desired = props.reported.get(name), props.desired.get(name)
        out.append((props.device_id, name, *_sql(reported), *_sql(desired)))
    return out


def _sql(value: Timed | None) -> tuple[str | None, int | None]:
    return (None, None) if value is None else (orjson.dumps(value[0]).decode(), value[1])


def _load(
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


def _save(
    props: tuple[int, int, int, int], rows: list[tuple[Any, ...]], conn: sqlite3.Connection
) -> None:
    """`props` is (device id, twin id, device created, version); `rows` from `property_rows`."""
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


def _delete_of(twin_ids: list[int], conn: sqlite3.Connection) -> None:
    for twin_id in twin_ids:
        conn.execute(
            "DELETE FROM device_properties WHERE device_id IN "
            "(SELECT device_id FROM device_property_versions WHERE twin_id = ?)",
            (twin_id,),
        )
        conn.execute("DELETE FROM device_property_versions WHERE twin_id = ?", (twin_id,))
