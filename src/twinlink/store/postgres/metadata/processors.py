"""Processors, their events and the FMUs uploaded to twins, in PostgreSQL."""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import FmuRecord, ProcessorEvent, ProcessorRecord
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.sql import Args
from twinlink.store.postgres.metadata.users import affected
from twinlink.store.rows import (
    FMU_COLUMNS,
    PROCESSOR_COLUMNS,
    PROCESSOR_FROM,
    event_of,
    fmu_of,
    processor_of,
)

# Events kept per processor; older ones are pruned as new ones arrive.
EVENTS_KEPT = 1000


def _json(value: Any) -> str:
    return orjson.dumps(value).decode()


class ProcessorTables:
    db: PostgresDatabase

    async def create_processor(
        self,
        twin_id: int,
        name: str,
        blueprint: str,
        spec: dict[str, Any],
        enabled: bool,
        created_by: int | None,
        now_ns: int,
    ) -> ProcessorRecord:
        try:
            async with self.db.transaction() as conn:
                pid = await conn.fetchval(
                    "INSERT INTO processors (twin_id, name, blueprint, spec, enabled, created_by,"
                    " created_ns, modified_ns) VALUES ($1, $2, $3, $4, $5, $6, $7, $7)"
                    " RETURNING id",
                    twin_id, name, blueprint, _json(spec), enabled, created_by, now_ns,
                )  # fmt: skip
                row = await conn.fetchrow(
                    f"SELECT {PROCESSOR_COLUMNS} {PROCESSOR_FROM} WHERE p.id = $1", pid
                )
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a processor {name!r}") from err
        assert row is not None
        return processor_of(row)

    async def update_processor(
        self, processor_id: int, spec: dict[str, Any], enabled: bool, now_ns: int
    ) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE processors SET spec = $1, enabled = $2, modified_ns = $3 WHERE id = $4",
                _json(spec), enabled, now_ns, processor_id,
            )  # fmt: skip

    async def delete_processor(self, processor_id: int) -> None:
        async with self.db.transaction() as conn:
            await conn.execute("DELETE FROM processors WHERE id = $1", processor_id)

    async def list_processors(self, twin_id: int | None = None) -> list[ProcessorRecord]:
        where, args = ("WHERE p.twin_id = $1", [twin_id]) if twin_id is not None else ("", [])
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {PROCESSOR_COLUMNS} {PROCESSOR_FROM} {where} ORDER BY p.name", *args
            )
        return [processor_of(r) for r in rows]

    async def add_processor_events(
        self, events: list[tuple[int, int, str, str, dict[str, Any]]]
    ) -> None:
        """Record (processor id, time ns, kind, message, data) rows; prune to EVENTS_KEPT."""
        async with self.db.transaction() as conn:
            await conn.executemany(
                "INSERT INTO processor_events (processor_id, time_ns, kind, message, data)"
                " SELECT $1, $2, $3, $4, $5 WHERE EXISTS (SELECT 1 FROM processors WHERE id = $1)",
                [(p, t, k, m, _json(d)) for p, t, k, m, d in events],
            )
            await conn.execute(
                "DELETE FROM processor_events e USING unnest($1::bigint[]) AS p(id)"
                " WHERE e.processor_id = p.id AND e.id <= (SELECT id FROM processor_events"
                " WHERE processor_id = p.id ORDER BY id DESC LIMIT 1 OFFSET $2)",
                list({e[0] for e in events}), EVENTS_KEPT,
            )  # fmt: skip

    async def list_processor_events(
        self, processor_id: int, limit: int, before_id: int | None = None, kind: str | None = None
    ) -> list[ProcessorEvent]:
        args = Args()
        sql = f"SELECT * FROM processor_events WHERE processor_id = {args(processor_id)}"
        if before_id is not None:
            sql += f" AND id < {args(before_id)}"
        if kind is not None:
            sql += f" AND kind = {args(kind)}"
        sql += f" ORDER BY id DESC LIMIT {args(limit)}"
        async with self.db.connection() as conn:
            rows = await conn.fetch(sql, *args)
        return [event_of(r) for r in rows]

    # -- FMUs ------------------------------------------------------------------------------

    async def put_fmu(
        self,
        twin_id: int,
        name: str,
        sha256: str,
        size: int,
        info: dict[str, Any],
        uploaded_by: int | None,
        now_ns: int,
    ) -> FmuRecord:
        """Create the FMU's row, or replace the one of that name."""
        async with self.db.transaction() as conn:
            row = await conn.fetchrow(
                "INSERT INTO fmus (twin_id, name, sha256, size, info, uploaded_by, uploaded_ns)"
                " VALUES ($1, $2, $3, $4, $5, $6, $7) ON CONFLICT (twin_id, name) DO UPDATE SET"
                " sha256 = excluded.sha256, size = excluded.size, info = excluded.info,"
                " uploaded_by = excluded.uploaded_by, uploaded_ns = excluded.uploaded_ns"
                f" RETURNING {FMU_COLUMNS}",
                twin_id, name, sha256, size, _json(info), uploaded_by, now_ns,
            )  # fmt: skip
        assert row is not None
        return fmu_of(row)

    async def list_fmus(self, twin_id: int) -> list[FmuRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {FMU_COLUMNS} FROM fmus WHERE twin_id = $1 ORDER BY name", twin_id
            )
        return [fmu_of(r) for r in rows]

    async def delete_fmu(self, twin_id: int, name: str) -> bool:
        async with self.db.transaction() as conn:
            status = await conn.execute(
                "DELETE FROM fmus WHERE twin_id = $1 AND name = $2", twin_id, name
            )
        return affected(status) > 0
