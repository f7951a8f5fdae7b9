"""The command log in history.db (`CommandStore`).

Writes go through the history writer (`SqliteHistory.write`), so they share its group commits
with telemetry: a command's state change costs no fsync of its own. Reads use a connection of
their own (own_reader.py).
"""

from __future__ import annotations

import sqlite3
from functools import partial
from typing import Any

import orjson

from twinlink.domain.commands import CommandRecord
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.history.own_reader import OwnReader

_COLUMNS = (
    "id, twin_id, device_id, device, name, args, state, queued, sent_by, created_ns, "
    "expires_ns, delivered_ns, finished_ns, result, error, late_status"
)
_UPSERT = (
    f"INSERT INTO commands ({_COLUMNS}) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
    "ON CONFLICT (id) DO UPDATE SET state = excluded.state, "
    "delivered_ns = excluded.delivered_ns, finished_ns = excluded.finished_ns, "
    "result = excluded.result, error = excluded.error, late_status = excluded.late_status"
)


class SqliteCommands:
    def __init__(self, history: SqliteHistory) -> None:
        self.history = history
        self.reader = OwnReader(history.path, "twinlink-cmd-read")

    async def open(self) -> None:
        await self.reader.open()

    async def close(self) -> None:
        await self.reader.close()

    async def save_commands(self, records: list[CommandRecord]) -> None:
        await self.history.write(partial(_save, [command_row(r) for r in records]))

    async def get_command(self, command_id: str) -> CommandRecord | None:
        return await self.reader.read(partial(_select_one, command_id))

    async def list_commands(
        self, twin_id: int, state: str | None, name: str | None, device: str | None, limit: int
    ) -> list[CommandRecord]:
        return await self.reader.read(partial(_select, twin_id, state, name, device, limit))

    async def open_commands(self) -> list[CommandRecord]:
        return await self.reader.read(_select_open)

    async def delete_commands_of(self, twin_ids: list[int]) -> None:
        await self.history.write(partial(_delete_of, twin_ids))


def command_row(r: CommandRecord) -> tuple[Any, ...]:
    return (
        r.id, r.twin_id, r.device_id, r.device, r.name, _json(r.args), r.state, int(r.queued),
        r.sent_by, r.created_ns, r.expires_ns, r.delivered_ns, r.finished_ns,
        None if r.result is None else _json(r.result), r.error, r.late_status,
    )  # fmt: skip


def record_from_row(row: tuple[Any, ...]) -> CommandRecord:
    (id_, twin_id, device_id, device, name, args, state, queued, sent_by, created_ns, expires_ns,
     delivered_ns, finished_ns, result, error, late_status) = row  # fmt: skip
    return CommandRecord(
        id=id_, twin_id=twin_id, device_id=device_id, device=device, name=name,
        args=orjson.loads(args), state=state, queued=bool(queued), sent_by=sent_by,
        created_ns=created_ns, expires_ns=expires_ns, delivered_ns=delivered_ns,
        finished_ns=finished_ns, result=None if result is None else orjson.loads(result),
        error=error, late_status=late_status,
    )  # fmt: skip


def _save(rows: list[tuple[Any, ...]], conn: sqlite3.Connection) -> None:
    conn.executemany(_UPSERT, rows)


def _select_one(command_id: str, conn: sqlite3.Connection) -> CommandRecord | None:
    row = conn.execute(f"SELECT {_COLUMNS} FROM commands WHERE id = ?", (command_id,)).fetchone()
    return None if row is None else record_from_row(row)


def _select(
    twin_id: int,
    state: str | None,
    name: str | None,
    device: str | None,
    limit: int,
    conn: sqlite3.Connection,
) -> list[CommandRecord]:
    sql = f"SELECT {_COLUMNS} FROM commands WHERE twin_id = ?"
    params: list[Any] = [twin_id]
    for column, value in (("state", state), ("name", name), ("device", device)):
        if value is not None:
            sql += f" AND {column} = ?"
            params.append(value)
    sql += " ORDER BY created_ns DESC, id LIMIT ?"
    params.append(limit)
    return [record_from_row(r) for r in conn.execute(sql, params)]


def _select_open(conn: sqlite3.Connection) -> list[CommandRecord]:
    rows = conn.execute(
        f"SELECT {_COLUMNS} FROM commands WHERE state IN ('pending', 'delivered') "
        "ORDER BY created_ns"
    )
    return [record_from_row(r) for r in rows]


def _delete_of(twin_ids: list[int], conn: sqlite3.Connection) -> None:
    conn.executemany("DELETE FROM commands WHERE twin_id = ?", [(i,) for i in twin_ids])


def _json(value: Any) -> str:
    return orjson.dumps(value).decode()
