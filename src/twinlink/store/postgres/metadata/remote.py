"""Remote twins in PostgreSQL."""

from __future__ import annotations

from twinlink.domain.remote import RemoteTwin
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.users import affected
from twinlink.store.remote import COLUMNS, like_pattern, remote_of, values_of

_NAMES = COLUMNS.split(", ")[1:]  # all but the id, which the database gives
_UPDATE = ", ".join(f"{c} = excluded.{c}" for c in _NAMES[1:])  # the dt-id kept
_WHERE = " OR ".join(
    f"lower({c}) LIKE $1 ESCAPE '\\'" for c in ("name", "dt_id", "url", "document")
)


class RemoteTables:
    db: PostgresDatabase

    async def put_remote_twin(self, twin: RemoteTwin) -> RemoteTwin:
        marks = ", ".join(f"${i}" for i in range(1, len(_NAMES) + 1))
        async with self.db.transaction() as conn:
            twin.id = await conn.fetchval(
                f"INSERT INTO remote_twins ({', '.join(_NAMES)}) VALUES ({marks})"
                f" ON CONFLICT (dt_id) DO UPDATE SET {_UPDATE} RETURNING id",
                *values_of(twin),
            )
        return twin

    async def _one_remote(self, where: str, arg: object) -> RemoteTwin | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(f"SELECT {COLUMNS} FROM remote_twins WHERE {where}", arg)
        return remote_of(row) if row is not None else None

    async def get_remote_twin(self, remote_id: int) -> RemoteTwin | None:
        return await self._one_remote("id = $1", remote_id)

    async def get_remote_twin_by_dt_id(self, dt_id: str) -> RemoteTwin | None:
        return await self._one_remote("dt_id = $1", dt_id)

    async def get_remote_twin_by_url(self, url: str) -> RemoteTwin | None:
        return await self._one_remote("url = $1 ORDER BY id LIMIT 1", url)

    async def list_remote_twins(self, q: str | None = None, limit: int = 1000) -> list[RemoteTwin]:
        async with self.db.connection() as conn:
            if q:
                rows = await conn.fetch(
                    f"SELECT {COLUMNS} FROM remote_twins WHERE {_WHERE}"
                    " ORDER BY name, id LIMIT $2",
                    like_pattern(q), limit,
                )  # fmt: skip
            else:
                rows = await conn.fetch(
                    f"SELECT {COLUMNS} FROM remote_twins ORDER BY name, id LIMIT $1", limit
                )
        return [remote_of(r) for r in rows]

    async def delete_remote_twin(self, remote_id: int) -> bool:
        async with self.db.transaction() as conn:
            return (
                affected(await conn.execute("DELETE FROM remote_twins WHERE id = $1", remote_id))
                > 0
            )
