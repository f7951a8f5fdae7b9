"""Remote twins in SQLite."""

from __future__ import annotations

import sqlite3

from twinlink.domain.remote import RemoteTwin
from twinlink.store.remote import COLUMNS, like_pattern, remote_of, values_of
from twinlink.store.sqlite.db import Database, next_id

_NAMES = COLUMNS.split(", ")
_UPDATE = ", ".join(f"{c} = excluded.{c}" for c in _NAMES[2:])  # the id and dt-id kept
_MATCH = "lower({0}) LIKE ? ESCAPE '\\'"
_WHERE = " OR ".join(_MATCH.format(c) for c in ("name", "dt_id", "url", "document"))


class RemoteTables:
    db: Database

    async def put_remote_twin(self, twin: RemoteTwin) -> RemoteTwin:
        def _put(c: sqlite3.Connection) -> int:
            row = c.execute("SELECT id FROM remote_twins WHERE dt_id = ?", (twin.dt_id,))
            found = row.fetchone()
            rid = int(found[0]) if found is not None else next_id(c, "remote_twins")
            marks = ", ".join("?" * len(_NAMES))
            c.execute(
                f"INSERT INTO remote_twins({COLUMNS}) VALUES ({marks})"
                f" ON CONFLICT(dt_id) DO UPDATE SET {_UPDATE}",
                (rid, *values_of(twin)),
            )
            return rid

        twin.id = await self.db.write(_put)
        return twin

    async def _one_remote(self, where: str, arg: object) -> RemoteTwin | None:
        row = await self.db.read(
            lambda c: c.execute(f"SELECT {COLUMNS} FROM remote_twins WHERE {where}", (arg,))
            .fetchone()
        )  # fmt: skip
        return remote_of(row) if row is not None else None

    async def get_remote_twin(self, remote_id: int) -> RemoteTwin | None:
        return await self._one_remote("id = ?", remote_id)

    async def get_remote_twin_by_dt_id(self, dt_id: str) -> RemoteTwin | None:
        return await self._one_remote("dt_id = ?", dt_id)

    async def get_remote_twin_by_url(self, url: str) -> RemoteTwin | None:
        return await self._one_remote("url = ? ORDER BY id LIMIT 1", url)

    async def list_remote_twins(self, q: str | None = None, limit: int = 1000) -> list[RemoteTwin]:
        where, args = (f"WHERE {_WHERE}", (like_pattern(q),) * 4) if q else ("", ())
        rows = await self.db.read(
            lambda c: c.execute(
                f"SELECT {COLUMNS} FROM remote_twins {where} ORDER BY name, id LIMIT ?",
                (*args, limit),
            ).fetchall()
        )
        return [remote_of(r) for r in rows]

    async def delete_remote_twin(self, remote_id: int) -> bool:
        return bool(
            await self.db.write(
                lambda c: c.execute("DELETE FROM remote_twins WHERE id = ?", (remote_id,)).rowcount
            )
        )
