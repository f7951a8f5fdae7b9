"""The command log in PostgreSQL (`CommandStore`): the table and semantics of the SQLite
backend's (store/sqlite/commands.py), each write one transaction of its own."""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.commands import CommandRecord
from twinlink.store.postgres.db import PostgresDatabase

_COLUMNS = (
    "id, twin_id, device_id, device, name, args, state, queued, sent_by, created_ns, "
    "expires_ns, delivered_ns, finished_ns, result, error, late_status"
)
_UPSERT = (
    f"INSERT INTO commands ({_COLUMNS}) "
    "VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16) "
    "ON CONFLICT (id) DO UPDATE SET state = excluded.state, "
    "delivered_ns = excluded.delivered_ns, finished_ns = excluded.finished_ns, "
    "result = excluded.result, error = excluded.error, late_status = excluded.late_status"
)


class PostgresCommands:
    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db

    async def open(self) -> None:
        """Nothing of its own to open: the shared database is opened before it."""

    async def close(self) -> None:
        """Nothing of its own to close."""

    async def save_commands(self, records: list[CommandRecord]) -> None:
        rows = [_row(r) for r in records]  # taken now: the caller goes on changing them
        async with self.db.transaction() as conn:
            await conn.executemany(_UPSERT, rows)

    async def get_command(self, command_id: str) -> CommandRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(f"SELECT {_COLUMNS} FROM commands WHERE id = $1", command_id)
        return None if row is None else _record(tuple(row))

    async def list_commands(
        self, twin_id: int, state: str | None, name: str | None, device: str | None, limit: int
    ) -> list[CommandRecord]:
        sql = f"SELECT {_COLUMNS} FROM commands WHERE twin_id = $1"
        params: list[Any] = [twin_id]
        for column, value in (("state", state), ("name", name), ("device", device)):
            if value is not None:
                params.append(value)
                sql += f" AND {column} = ${len(params)}"
        params.append(limit)
        sql += f" ORDER BY created_ns DESC, id LIMIT ${len(params)}"
        async with self.db.connection() as conn:
            rows = await conn.fetch(sql, *params)
        return [_record(tuple(r)) for r in rows]

    async def open_commands(self) -> list[CommandRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {_COLUMNS} FROM commands WHERE state IN ('pending', 'delivered') "
                "ORDER BY created_ns"
            )
        return [_record(tuple(r)) for r in rows]

    async def delete_commands_of(self, twin_ids: list[int]) -> None:
        async with self.db.transaction() as conn:
            await conn.execute("DELETE FROM commands WHERE twin_id = ANY($1::bigint[])", twin_ids)


def _row(r: CommandRecord) -> tuple[Any, ...]:
    return (
        r.id, r.twin_id, r.device_id, r.device, r.name, _json(r.args), r.state, r.queued,
        r.sent_by, r.created_ns, r.expires_ns, r.delivered_ns, r.finished_ns,
        None if r.result is None else _json(r.result), r.error, r.late_status,
    )  # fmt: skip


def _record(row: tuple[Any, ...]) -> CommandRecord:
    (id_, twin_id, device_id, device, name, args, state, queued, sent_by, created_ns, expires_ns,
     delivered_ns, finished_ns, result, error, late_status) = row  # fmt: skip
    return CommandRecord(
        id=id_, twin_id=twin_id, device_id=device_id, device=device, name=name,
        args=orjson.loads(args), state=state, queued=queued, sent_by=sent_by,
        created_ns=created_ns, expires_ns=expires_ns, delivered_ns=delivered_ns,
        finished_ns=finished_ns, result=None if result is None else orjson.loads(result),
        error=error, late_status=late_status,
    )  # fmt: skip


def _json(value: Any) -> str:
    return orjson.dumps(value).decode()
