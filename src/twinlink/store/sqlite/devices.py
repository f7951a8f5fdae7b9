"""Devices and their credentials in SQLite."""

from __future__ import annotations

import sqlite3
from collections.abc import Mapping

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import Device
from twinlink.store.rows import DEVICE_COLUMNS, DEVICE_FROM, device_of
from twinlink.store.sqlite.db import Database, next_id


class DeviceTables:
    db: Database

    async def create_device(
        self, twin_id: int, name: str, description: str, token_hash: bytes, prefix: str, now_ns: int
    ) -> Device:
        def _create(c: sqlite3.Connection) -> Device:
            device_id = next_id(c, "devices")
            c.execute(
                "INSERT INTO devices(id, twin_id, name, description, token_hash, prefix,"
                " created_ns) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (device_id, twin_id, name, description, token_hash, prefix, now_ns),
            )
            return device_of(
                c.execute(
                    f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} WHERE d.id = ?", (device_id,)
                ).fetchone()
            )

        try:
            return await self.db.write(_create)
        except WriteConflictError as err:  # another request created it meanwhile
            raise ConflictError(f"the twin already has a device {name!r}") from err

    async def list_devices(self, twin_id: int) -> list[Device]:
        rows = await self.db.read(
            lambda c: c.execute(
                f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} WHERE d.twin_id = ? ORDER BY d.name",
                (twin_id,),
            ).fetchall()
        )
        return [device_of(r) for r in rows]

    async def get_device(self, twin_id: int, name: str) -> Device | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} WHERE d.twin_id = ? AND d.name = ?",
                (twin_id, name),
            ).fetchone()
        )
        return device_of(row) if row else None

    async def find_device(self, token_hash: bytes) -> Device | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {DEVICE_COLUMNS} {DEVICE_FROM} WHERE d.token_hash = ?", (token_hash,)
            ).fetchone()
        )
        return device_of(row) if row else None

    async def set_device_token(self, device_id: int, token_hash: bytes, prefix: str) -> None:
        await self.db.write(
            lambda c: c.execute(
                "UPDATE devices SET token_hash = ?, prefix = ? WHERE id = ?",
                (token_hash, prefix, device_id),
            )
        )

    async def touch_devices(self, times: Mapping[int, int]) -> None:
        """Record when devices were last seen ({device id: ns}), never moving a time back."""
        rows = [(ns, device_id, ns) for device_id, ns in times.items()]
        await self.db.write(
            lambda c: c.executemany(
                "UPDATE devices SET last_seen_ns = ? WHERE id = ?"
                " AND (last_seen_ns IS NULL OR last_seen_ns < ?)",
                rows,
            )
        )

    async def delete_device(self, device_id: int) -> None:
        await self.db.write(lambda c: c.execute("DELETE FROM devices WHERE id = ?", (device_id,)))
