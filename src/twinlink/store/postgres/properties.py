"""Device properties in PostgreSQL (`PropertyStore`): the tables and semantics of the SQLite
backend's (store/sqlite/properties.py), each save one transaction."""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.properties import DeviceProperties, Timed
from twinlink.store.postgres.db import PostgresDatabase

_UPSERT_VERSION = (
    "INSERT INTO device_property_versions (device_id, twin_id, device_created_ns, version) "
    "VALUES ($1, $2, $3, $4) ON CONFLICT (device_id) DO UPDATE SET twin_id = excluded.twin_id, "
    "device_created_ns = excluded.device_created_ns, version = excluded.version"
)
_UPSERT_PROPERTY = (
    "INSERT INTO device_properties (device_id, name, reported, reported_ns, desired, "
    "desired_ns) VALUES ($1, $2, $3, $4, $5, $6) ON CONFLICT (device_id, name) DO UPDATE SET "
    "reported = excluded.reported, reported_ns = excluded.reported_ns, "
    "desired = excluded.desired, desired_ns = excluded.desired_ns"
)


class PostgresProperties:
    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db

    async def open(self) -> None:
        """Nothing of its own to open: the shared database is opened before it."""

    async def close(self) -> None:
        """Nothing of its own to close."""

    async def load_properties(
        self, device_id: int, twin_id: int, created_ns: int
    ) -> DeviceProperties:
        props = DeviceProperties(device_id, twin_id, created_ns)
        async with self.db.connection() as conn:
            head = await conn.fetchrow(
                "SELECT device_created_ns, version FROM device_property_versions "
                "WHERE device_id = $1",
                device_id,
            )
            if head is None or head[0] != created_ns:
                return props  # nothing stored, or rows of a deleted device that had the id
            rows = await conn.fetch(
                "SELECT name, reported, reported_ns, desired, desired_ns FROM device_properties "
                "WHERE device_id = $1",
                device_id,
            )
        props.version = head[1]
        for name, reported, reported_ns, desired, desired_ns in rows:
            if reported is not None:
                props.reported[name] = (orjson.loads(reported), reported_ns)
            if desired is not None:
                props.desired[name] = (orjson.loads(desired), desired_ns)
        return props

    async def save_properties(self, props: DeviceProperties, names: list[str]) -> None:
        # Taken now: the caller goes on changing `props` while the transaction runs.
        head = (props.device_id, props.twin_id, props.device_created_ns, props.version)
        rows = _rows(props, names)
        async with self.db.transaction() as conn:
            # Locks the device's row, so two nodes saving one device's properties queue.
            old = await conn.fetchval(
                "SELECT device_created_ns FROM device_property_versions WHERE device_id = $1 "
                "FOR UPDATE",
                props.device_id,
            )
            if old is not None and old != props.device_created_ns:  # a deleted device's rows
                await conn.execute(
                    "DELETE FROM device_properties WHERE device_id = $1", props.device_id
                )
            await conn.execute(_UPSERT_VERSION, *head)
            await conn.executemany(_UPSERT_PROPERTY, rows)

    async def delete_properties_of(self, twin_ids: list[int]) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "DELETE FROM device_properties WHERE device_id IN (SELECT device_id FROM "
                "device_property_versions WHERE twin_id = ANY($1::bigint[]))",
                twin_ids,
            )
            await conn.execute(
                "DELETE FROM device_property_versions WHERE twin_id = ANY($1::bigint[])",
                twin_ids,
            )


def _rows(props: DeviceProperties, names: list[str]) -> list[tuple[Any, ...]]:
    """(device id, name, reported, reported_ns, desired, desired_ns) of each of `names`."""
    out = []
    for name in names:
        reported, desired = props.reported.get(name), props.desired.get(name)
        out.append((props.device_id, name, *_sql(reported), *_sql(desired)))
    return out


def _sql(value: Timed | None) -> tuple[str | None, int | None]:
    return (None, None) if value is None else (orjson.dumps(value[0]).decode(), value[1])
