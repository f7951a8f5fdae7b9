"""Co-simulations made through the API in PostgreSQL."""

from __future__ import annotations

from twinlink.domain.cosims import CosimRecord
from twinlink.store.cosims import COLUMNS, cosim_of, values_of
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.users import affected

_NAMES = COLUMNS.split(", ")[1:]  # all but the id, which the database gives
_SET = ", ".join(f"{c} = ${i}" for i, c in enumerate(_NAMES, start=1))


class CosimTables:
    db: PostgresDatabase

    async def create_cosim(self, record: CosimRecord) -> CosimRecord:
        marks = ", ".join(f"${i}" for i in range(1, len(_NAMES) + 1))
        async with self.db.transaction() as conn:
            record.id = await conn.fetchval(
                f"INSERT INTO cosims ({', '.join(_NAMES)}) VALUES ({marks}) RETURNING id",
                *values_of(record),
            )
        return record

    async def save_cosim(self, record: CosimRecord) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                f"UPDATE cosims SET {_SET} WHERE id = ${len(_NAMES) + 1}",
                *values_of(record), record.id,
            )  # fmt: skip

    async def get_cosim(self, cosim_id: int) -> CosimRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(f"SELECT {COLUMNS} FROM cosims WHERE id = $1", cosim_id)
        return cosim_of(row) if row is not None else None

    async def list_cosims(self, state: str | None = None) -> list[CosimRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {COLUMNS} FROM cosims WHERE ($1::text IS NULL OR state = $1)"
                " ORDER BY id DESC",
                state,
            )
        return [cosim_of(r) for r in rows]

    async def delete_cosim(self, cosim_id: int) -> bool:
        async with self.db.transaction() as conn:
            return affected(await conn.execute("DELETE FROM cosims WHERE id = $1", cosim_id)) > 0

    async def fail_running_cosims(
        self, nodes: list[str] | None, message: str, now_ns: int
    ) -> list[CosimRecord]:
        async with self.db.transaction() as conn:
            rows = await conn.fetch(
                f"SELECT {COLUMNS} FROM cosims WHERE state = 'running'"
                " AND ($1::text[] IS NULL OR node = ANY($1::text[])) ORDER BY id FOR UPDATE",
                nodes,
            )
            found = [cosim_of(r) for r in rows]
            await conn.execute(
                "UPDATE cosims SET state = 'failed', message = $1, ended_ns = $2"
                " WHERE id = ANY($3::bigint[])",
                message, now_ns, [r.id for r in found],
            )  # fmt: skip
        return found
