"""The gateway's services and audit log, in SQLite."""

from __future__ import annotations

import sqlite3
from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import AuditEntry, ServiceRecord
from twinlink.store.rows import AUDIT_COLUMNS, SERVICE_COLUMNS, audit_of, service_of
from twinlink.store.sqlite.db import Database


class GatewayTables:
    db: Database

    async def list_services(self, twin_id: int | None = None) -> list[ServiceRecord]:
        where, args = ("WHERE twin_id = ?", (twin_id,)) if twin_id is not None else ("", ())
        sql = f"SELECT {SERVICE_COLUMNS} FROM gateway_services {where} ORDER BY name"
        return await self.db.read(lambda c: [service_of(r) for r in c.execute(sql, args)])

    async def put_service(self, record: ServiceRecord, create: bool) -> ServiceRecord:
        """Insert `record` (create) or replace the row of its twin and name."""

        def _put(c: sqlite3.Connection) -> ServiceRecord:
            values = (
                orjson.dumps(record.settings),
                record.secret,
                record.auth_origin,
                record.modified_ns,
            )
            if create:
                c.execute(
                    "INSERT INTO gateway_services(twin_id, name, source, settings, secret,"
                    " auth_origin, modified_ns, created_by, created_ns)"
                    " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (record.twin_id, record.name, record.source, *values, record.created_by,
                     record.created_ns),
                )  # fmt: skip
            else:
                c.execute(
                    "UPDATE gateway_services SET settings = ?, secret = ?, auth_origin = ?,"
                    " modified_ns = ? WHERE twin_id = ? AND name = ?",
                    (*values, record.twin_id, record.name),
                )
            row = c.execute(
                f"SELECT {SERVICE_COLUMNS} FROM gateway_services WHERE twin_id = ? AND name = ?",
                (record.twin_id, record.name),
            ).fetchone()
            return service_of(row)

        try:
            return await self.db.write(_put)
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a service {record.name!r}") from err

    async def delete_service(self, twin_id: int, name: str) -> bool:
        cursor = await self.db.write(
            lambda c: c.execute(
                "DELETE FROM gateway_services WHERE twin_id = ? AND name = ?", (twin_id, name)
            )
        )
        return bool(cursor.rowcount)

    async def add_audit(self, entries: list[AuditEntry], keep_after_ns: int) -> None:
        """Append entries (one transaction) and delete those older than `keep_after_ns`."""

        def _add(c: sqlite3.Connection) -> None:
            c.executemany(
                f"INSERT INTO gateway_audit({AUDIT_COLUMNS}) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)",
                [
                    (e.time_ns, e.twin, e.service, e.caller, e.method, e.path, e.status,
                     e.outcome, e.bytes_in, e.bytes_out, e.upstream_ms, e.total_ms)
                    for e in entries
                ],
            )  # fmt: skip
            c.execute("DELETE FROM gateway_audit WHERE time_ns < ?", (keep_after_ns,))

        await self.db.write(_add)

    async def list_audit(
        self, filters: dict[str, Any], limit: int, before_id: int | None = None
    ) -> list[AuditEntry]:
        """Newest first. `filters` may hold twin, service, caller, method, status, since_ns,
        until_ns, twins (a list of slugs the caller may see, or None for all)."""
        sql = f"SELECT id, {AUDIT_COLUMNS} FROM gateway_audit WHERE 1 = 1"
        args: list[Any] = []
        for key in ("twin", "service", "caller", "method", "status"):
            if filters.get(key) is not None:
                sql += f" AND {key} = ?"
                args.append(filters[key])
        if filters.get("since_ns") is not None:
            sql += " AND time_ns >= ?"
            args.append(filters["since_ns"])
        if filters.get("until_ns") is not None:
            sql += " AND time_ns < ?"
            args.append(filters["until_ns"])
        twins = filters.get("twins")
        if twins is not None:
            sql += f" AND twin IN ({','.join('?' * len(twins))})"
            args.extend(twins)
        if before_id is not None:
            sql += " AND id < ?"
            args.append(before_id)
        sql += " ORDER BY id DESC LIMIT ?"
        args.append(limit)
        return await self.db.read(lambda c: [audit_of(r) for r in c.execute(sql, args)])
