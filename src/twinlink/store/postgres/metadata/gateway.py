"""The gateway's services and audit log, in PostgreSQL."""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import AuditEntry, ServiceRecord
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.sql import Args
from twinlink.store.postgres.metadata.users import affected
from twinlink.store.rows import AUDIT_COLUMNS, AUDIT_FIELDS, SERVICE_COLUMNS, audit_of, service_of


class GatewayTables:
    db: PostgresDatabase

    async def list_services(self, twin_id: int | None = None) -> list[ServiceRecord]:
        where, args = ("WHERE twin_id = $1", [twin_id]) if twin_id is not None else ("", [])
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {SERVICE_COLUMNS} FROM gateway_services {where} ORDER BY name", *args
            )
        return [service_of(r) for r in rows]

    async def put_service(self, record: ServiceRecord, create: bool) -> ServiceRecord:
        """Insert `record` (create) or replace the row of its twin and name."""
        values = (
            orjson.dumps(record.settings).decode(),
            record.secret,
            record.auth_origin,
            record.modified_ns,
        )
        try:
            async with self.db.transaction() as conn:
                if create:
                    await conn.execute(
                        "INSERT INTO gateway_services (settings, secret, auth_origin,"
                        " modified_ns, twin_id, name, source, created_by, created_ns)"
                        " VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9)",
                        *values, record.twin_id, record.name, record.source, record.created_by,
                        record.created_ns,
                    )  # fmt: skip
                else:
                    await conn.execute(
                        "UPDATE gateway_services SET settings = $1, secret = $2,"
                        " auth_origin = $3, modified_ns = $4 WHERE twin_id = $5 AND name = $6",
                        *values, record.twin_id, record.name,
                    )  # fmt: skip
                row = await conn.fetchrow(
                    f"SELECT {SERVICE_COLUMNS} FROM gateway_services"
                    " WHERE twin_id = $1 AND name = $2",
                    record.twin_id, record.name,
                )  # fmt: skip
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a service {record.name!r}") from err
        assert row is not None
        return service_of(row)

    async def delete_service(self, twin_id: int, name: str) -> bool:
        async with self.db.transaction() as conn:
            status = await conn.execute(
                "DELETE FROM gateway_services WHERE twin_id = $1 AND name = $2", twin_id, name
            )
        return affected(status) > 0

    async def add_audit(self, entries: list[AuditEntry], keep_after_ns: int) -> None:
        """Append entries (one transaction) and delete those older than `keep_after_ns`."""
        async with self.db.transaction() as conn:
            await conn.copy_records_to_table(
                "gateway_audit",
                records=[tuple(getattr(e, f) for f in AUDIT_FIELDS) for e in entries],
                columns=AUDIT_FIELDS,
            )
            await conn.execute("DELETE FROM gateway_audit WHERE time_ns < $1", keep_after_ns)

    async def list_audit(
        self, filters: dict[str, Any], limit: int, before_id: int | None = None
    ) -> list[AuditEntry]:
        """Newest first. `filters` may hold twin, service, caller, method, status, since_ns,
        until_ns, twins (a list of slugs the caller may see, or None for all)."""
        args = Args()
        sql = f"SELECT id, {AUDIT_COLUMNS} FROM gateway_audit WHERE true"
        for key in ("twin", "service", "caller", "method", "status"):
            if filters.get(key) is not None:
                sql += f" AND {key} = {args(filters[key])}"
        if filters.get("since_ns") is not None:
            sql += f" AND time_ns >= {args(filters['since_ns'])}"
        if filters.get("until_ns") is not None:
            sql += f" AND time_ns < {args(filters['until_ns'])}"
        if filters.get("twins") is not None:
            sql += f" AND twin = ANY({args(list(filters['twins']))}::text[])"
        if before_id is not None:
            sql += f" AND id < {args(before_id)}"
        sql += f" ORDER BY id DESC LIMIT {args(limit)}"
        async with self.db.connection() as conn:
            rows = await conn.fetch(sql, *args)
        return [audit_of(r) for r in rows]
