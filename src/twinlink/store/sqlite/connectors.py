"""Connectors (UDP datasources, OPC UA clients...) in SQLite."""

from __future__ import annotations

import sqlite3
from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import ConnectorRecord
from twinlink.store.rows import CONNECTOR_COLUMNS, CONNECTOR_FROM, connector_of
from twinlink.store.sqlite.db import Database, next_id


class ConnectorTables:
    db: Database

    async def create_connector(
        self,
        twin_id: int,
        device_id: int,
        name: str,
        kind: str,
        settings: dict[str, Any],
        secret: bytes | None,
        enabled: bool,
        created_by: int | None,
        now_ns: int,
    ) -> ConnectorRecord:
        def _create(c: sqlite3.Connection) -> ConnectorRecord:
            cid = next_id(c, "connectors")
            c.execute(
                "INSERT INTO connectors(id, twin_id, device_id, name, kind, settings, secret,"
                " enabled, created_by, created_ns, modified_ns)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (cid, twin_id, device_id, name, kind, orjson.dumps(settings), secret, enabled,
                 created_by, now_ns, now_ns),
            )  # fmt: skip
            return connector_of(
                c.execute(
                    f"SELECT {CONNECTOR_COLUMNS} {CONNECTOR_FROM} WHERE c.id = ?", (cid,)
                ).fetchone()
            )

        try:
            return await self.db.write(_create)
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a connector {name!r}") from err

    async def update_connector(
        self,
        connector_id: int,
        settings: dict[str, Any],
        secret: bytes | None,
        enabled: bool,
        now_ns: int,
    ) -> None:
        await self.db.write(
            lambda c: c.execute(
                "UPDATE connectors SET settings = ?, secret = ?, enabled = ?, modified_ns = ?"
                " WHERE id = ?",
                (orjson.dumps(settings), secret, enabled, now_ns, connector_id),
            )
        )

    async def delete_connector(self, connector_id: int) -> None:
        await self.db.write(
            lambda c: c.execute("DELETE FROM connectors WHERE id = ?", (connector_id,))
        )

    async def list_connectors(self, twin_id: int | None = None) -> list[ConnectorRecord]:
        where, args = ("WHERE c.twin_id = ?", (twin_id,)) if twin_id is not None else ("", ())
        return await self.db.read(
            lambda c: [
                connector_of(row)
                for row in c.execute(
                    f"SELECT {CONNECTOR_COLUMNS} {CONNECTOR_FROM} {where} ORDER BY c.id", args
                )
            ]
        )
