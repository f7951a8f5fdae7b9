"""Devices and their credentials in PostgreSQL."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import Device
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.rows import DEVICE_COLUMNS, DEVICE_FROM, device_of


class DeviceTables:
    db: PostgresDatabase

    async def _devices(self, where: str, *args: Any) -> list[Device]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} {where}", *args)
        return [device_of(r) for r in rows]

    async def create_device(
        self, twin_id: int, name: str, description: str, token_hash: bytes, prefix: str, now_ns: int
    ) -> Device:
        try:
            async with self.db.transaction() as conn:
                device_id = await conn.fetchval(
                    "INSERT INTO devices (twin_id, name, description, token_hash, prefix,"
                    " created_ns) VALUES ($1, $2, $3, $4, $5, $6) RETURNING id",
                    twin_id, name, description, token_hash, prefix, now_ns,
                )  # fmt: skip
                row = await conn.fetchrow(
                    f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} WHERE d.id = $1", device_id
                )
        except WriteConflictError as err:  # another request created it meanwhile
            raise ConflictError(f"the twin already has a device {name!r}") from err
        assert row is not None
        return device_of(row)

    async def list_devices(self, twin_id: int) -> list[Device]:
        return await self._devices("WHERE d.twin_id = $1 ORDER BY d.name", twin_id)

    async def get_device(self, twin_id: int, name: str) -> Device | None:
        found = await self._devices("WHERE d.twin_id = $1 AND d.name = $2", twin_id, name)
        return found[0] if found else None

    async def find_device(self, token_hash: bytes) -> Device | None:
        found = await self._devices("WHERE d.token_hash = $1", token_hash)
        return found[0] if found else None

    async def set_device_token(self, device_id: int, token_hash: bytes, prefix: str) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE devices SET token_hash = $1, prefix = $2 WHERE id = $3",
                token_hash, prefix, device_id,
            )  # fmt: skip

    async def touch_devices(self, times: Mapping[int, int]) -> None:
        """Record when devices were last seen ({device id: ns}), never moving a time back."""
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE devices d SET last_seen_ns = t.ns FROM unnest($1::bigint[],"
                " $2::bigint[]) AS t(id, ns) WHERE d.id = t.id"
                " AND (d.last_seen_ns IS NULL OR d.last_seen_ns < t.ns)",
                list(times), list(times.values()),
            )  # fmt: skip

    async def delete_device(self, device_id: int) -> None:
        async with self.db.transaction() as conn:
            await conn.execute("DELETE FROM devices WHERE id = $1", device_id)
