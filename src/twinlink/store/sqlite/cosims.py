"""Co-simulations made through the API in SQLite."""

from __future__ import annotations

import sqlite3

from twinlink.domain.cosims import CosimRecord
from twinlink.store.cosims import COLUMNS, cosim_of, values_of
from twinlink.store.sqlite.db import Database, next_id

_SET = ", ".join(f"{c} = ?" for c in COLUMNS.split(", ")[1:])


class CosimTables:
    db: Database

    async def create_cosim(self, record: CosimRecord) -> CosimRecord:
        def _create(c: sqlite3.Connection) -> int:
            cid = next_id(c, "cosims")
            marks = ", ".join("?" * len(COLUMNS.split(", ")))
            c.execute(f"INSERT INTO cosims({COLUMNS}) VALUES ({marks})", (cid, *values_of(record)))
            return cid

        record.id = await self.db.write(_create)
        return record

    async def save_cosim(self, record: CosimRecord) -> None:
        args = (*values_of(record), record.id)
        await self.db.write(lambda c: c.execute(f"UPDATE cosims SET {_SET} WHERE id = ?", args))

    async def get_cosim(self, cosim_id: int) -> CosimRecord | None:
        row = await self.db.read(
            lambda c: c.execute(f"SELECT {COLUMNS} FROM cosims WHERE id = ?", (cosim_id,))
            .fetchone()
        )  # fmt: skip
        return cosim_of(row) if row is not None else None

    async def list_cosims(self, state: str | None = None) -> list[CosimRecord]:
        where, args = ("WHERE state = ?", (state,)) if state is not None else ("", ())
        rows = await self.db.read(
            lambda c: c.execute(
                f"SELECT {COLUMNS} FROM cosims {where} ORDER BY id DESC", args
            ).fetchall()
        )
        return [cosim_of(r) for r in rows]

    async def delete_cosim(self, cosim_id: int) -> bool:
        return bool(
            await self.db.write(
                lambda c: c.execute("DELETE FROM cosims WHERE id = ?", (cosim_id,)).rowcount
            )
        )

    async def fail_running_cosims(
        self, nodes: list[str] | None, message: str, now_ns: int
    ) -> list[CosimRecord]:
        def _fail(c: sqlite3.Connection) -> list[CosimRecord]:
            rows = c.execute(f"SELECT {COLUMNS} FROM cosims WHERE state = 'running'")
            found = [cosim_of(r) for r in rows.fetchall()]
            found = [r for r in found if nodes is None or r.node in nodes]
            c.executemany(
                "UPDATE cosims SET state = 'failed', message = ?, ended_ns = ? WHERE id = ?",
                [(message, now_ns, r.id) for r in found],
            )
            return found

        return await self.db.write(_fail)
