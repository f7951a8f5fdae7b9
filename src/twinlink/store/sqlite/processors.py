"""Processors, their events and the FMUs uploaded to twins, in SQLite."""

from __future__ import annotations

import sqlite3
from typing import Any

import orjson

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import FmuRecord, ProcessorEvent, ProcessorRecord
from twinlink.store.rows import (
    FMU_COLUMNS,
    PROCESSOR_COLUMNS,
    PROCESSOR_FROM,
    event_of,
    fmu_of,
    processor_of,
)
from twinlink.store.sqlite.db import Database, next_id

# Events kept per processor; older ones are pruned as new ones arrive.
EVENTS_KEPT = 1000


class ProcessorTables:
    db: Database

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
        def _create(c: sqlite3.Connection) -> ProcessorRecord:
            pid = next_id(c, "processors")
            c.execute(
                "INSERT INTO processors(id, twin_id, name, blueprint, spec, enabled, created_by,"
                " created_ns, modified_ns) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (pid, twin_id, name, blueprint, orjson.dumps(spec), enabled, created_by, now_ns,
                 now_ns),
            )  # fmt: skip
            return processor_of(
                c.execute(
                    f"SELECT {PROCESSOR_COLUMNS} {PROCESSOR_FROM} WHERE p.id = ?", (pid,)
                ).fetchone()
            )

        try:
            return await self.db.write(_create)
        except WriteConflictError as err:
            raise ConflictError(f"the twin already has a processor {name!r}") from err

    async def update_processor(
        self, processor_id: int, spec: dict[str, Any], enabled: bool, now_ns: int
    ) -> None:
        await self.db.write(
            lambda c: c.execute(
                "UPDATE processors SET spec = ?, enabled = ?, modified_ns = ? WHERE id = ?",
                (orjson.dumps(spec), enabled, now_ns, processor_id),
            )
        )

    async def delete_processor(self, processor_id: int) -> None:
        await self.db.write(
            lambda c: c.execute("DELETE FROM processors WHERE id = ?", (processor_id,))
        )

    async def list_processors(self, twin_id: int | None = None) -> list[ProcessorRecord]:
        where, args = ("WHERE p.twin_id = ?", (twin_id,)) if twin_id is not None else ("", ())
        return await self.db.read(
            lambda c: [
                processor_of(r)
                for r in c.execute(
                    f"SELECT {PROCESSOR_COLUMNS} {PROCESSOR_FROM} {where} ORDER BY p.name", args
                )
            ]
        )

    async def add_processor_events(
        self, events: list[tuple[int, int, str, str, dict[str, Any]]]
    ) -> None:
        """Record (processor id, time ns, kind, message, data) rows; prune to EVENTS_KEPT."""

        def _add(c: sqlite3.Connection) -> None:
            c.executemany(
                "INSERT INTO processor_events(processor_id, time_ns, kind, message, data)"
                " SELECT ?, ?, ?, ?, ? WHERE EXISTS (SELECT 1 FROM processors WHERE id = ?)",
                [(p, t, k, m, orjson.dumps(d), p) for p, t, k, m, d in events],
            )
            for pid in {e[0] for e in events}:
                c.execute(
                    "DELETE FROM processor_events WHERE processor_id = ? AND id <= ("
                    " SELECT id FROM processor_events WHERE processor_id = ?"
                    " ORDER BY id DESC LIMIT 1 OFFSET ?)",
                    (pid, pid, EVENTS_KEPT),
                )

        await self.db.write(_add)

    async def list_processor_events(
        self, processor_id: int, limit: int, before_id: int | None = None, kind: str | None = None
    ) -> list[ProcessorEvent]:
        sql = "SELECT * FROM processor_events WHERE processor_id = ?"
        args: list[Any] = [processor_id]
        if before_id is not None:
            sql += " AND id < ?"
            args.append(before_id)
        if kind is not None:
            sql += " AND kind = ?"
            args.append(kind)
        sql += " ORDER BY id DESC LIMIT ?"
        args.append(limit)
        return await self.db.read(lambda c: [event_of(r) for r in c.execute(sql, args)])

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

        def _put(c: sqlite3.Connection) -> FmuRecord:
            c.execute(
                "INSERT INTO fmus(twin_id, name, sha256, size, info, uploaded_by, uploaded_ns)"
                " VALUES (?, ?, ?, ?, ?, ?, ?) ON CONFLICT (twin_id, name) DO UPDATE SET"
                " sha256 = excluded.sha256, size = excluded.size, info = excluded.info,"
                " uploaded_by = excluded.uploaded_by, uploaded_ns = excluded.uploaded_ns",
                (twin_id, name, sha256, size, orjson.dumps(info), uploaded_by, now_ns),
            )
            row = c.execute(
                f"SELECT {FMU_COLUMNS} FROM fmus WHERE twin_id = ? AND name = ?", (twin_id, name)
            ).fetchone()
            return fmu_of(row)

        return await self.db.write(_put)

    async def list_fmus(self, twin_id: int) -> list[FmuRecord]:
        return await self.db.read(
            lambda c: [
                fmu_of(r)
                for r in c.execute(
                    f"SELECT {FMU_COLUMNS} FROM fmus WHERE twin_id = ? ORDER BY name", (twin_id,)
                )
            ]
        )

    async def delete_fmu(self, twin_id: int, name: str) -> bool:
        cursor = await self.db.write(
            lambda c: c.execute("DELETE FROM fmus WHERE twin_id = ? AND name = ?", (twin_id, name))
        )
        return bool(cursor.rowcount)
