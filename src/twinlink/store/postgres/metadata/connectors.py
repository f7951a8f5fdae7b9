"""Connectors (UDP datasources, OPC UA clients...) in PostgreSQL."""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import ConnectorRecord
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.rows import CONNECTOR_COLUMNS, CONNECTOR_FROM, connector_of


class ConnectorTables:
    db: PostgresDatabase

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
        try:
            async with self.db.transaction() as conn:
                cid = await conn.fetchval(
                    "INSERT INTO connectors (twin_id, device_id, name, kind, settings, secret,"
                    " enabled, created_by, created_ns, modified_ns)"
                    " VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $9) RETURNING id",
                    twin_id, device_id, name, kind, orjson.dumps(settings).decode(), secret,
                    enabled, created_by, now_ns,
                )  # fmt: skip
                row = await conn.fetchrow(
                    f"SELECT {CONNECTOR_COLUMNS} {CONNECTOR_FROM} WHERE c.id = $1", cid
                )
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a connector {name!r}") from err
        assert row is not None
        return connector_of(row)

    async def update_connector(
        self,
        connector_id: int,
        settings: dict[str, Any],
        secret: bytes | None,
        enabled: bool,
        now_ns: int,
    ) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE connectors SET settings = $1, secret = $2, enabled = $3,"
                " modified_ns = $4 WHERE id = $5",
                orjson.dumps(settings).decode(), secret, enabled, now_ns, connector_id,
            )  # fmt: skip

    async def delete_connector(self, connector_id: int) -> None:
        async with self.db.transaction() as conn:
            await conn.execute("DELETE FROM connectors WHERE id = $1", connector_id)

    async def list_connectors(self, twin_id: int | None = None) -> list[ConnectorRecord]:
        where, args = ("WHERE c.twin_id = $1", [twin_id]) if twin_id is not None else ("", [])
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {CONNECTOR_COLUMNS} {CONNECTOR_FROM} {where} ORDER BY c.id", *args
            )
        return [connector_of(r) for r in rows]
