"""Commands and properties in history.db: the SQL, a read connection of our own, and the
write-behind that turns many state changes into one statement per group commit.

Writes go through the history writer (`history.write(fn)`), so they share its group commits
with telemetry. Reads use a separate WAL connection on a thread of its own: they never wait
for a commit and never occupy the writer's thread.
"""

from __future__ import annotations

import asyncio
import logging
import sqlite3
from collections.abc import Awaitable, Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from pathlib import Path
from typing import Any, TypeVar

import orjson

from twinlink.commands.model import CommandRecord
from twinlink.domain.errors import StorageError

T = TypeVar("T")
log = logging.getLogger("twinlink.commands")
Write = Callable[[Callable[[sqlite3.Connection], Any]], Awaitable[Any]]

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


class ReadConnection:
    """A read-only connection to history.db, used from one thread of its own."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="twinlink-cmd-read")
        self._conn: sqlite3.Connection | None = None

    async def open(self) -> None:
        def _open() -> None:
            conn = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            conn.execute("PRAGMA query_only=ON")
            conn.execute("PRAGMA busy_timeout=10000")
            self._conn = conn

        await asyncio.get_running_loop().run_in_executor(self._executor, _open)

    async def close(self) -> None:
        def _close() -> None:
            if self._conn is not None:
                self._conn.close()
                self._conn = None

        await asyncio.get_running_loop().run_in_executor(self._executor, _close)
        self._executor.shutdown(wait=True)

    async def read(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        def _run() -> T:
            if self._conn is None:
                raise RuntimeError("the command store is not open")
            return fn(self._conn)

        return await asyncio.get_running_loop().run_in_executor(self._executor, _run)


# -- commands --------------------------------------------------------------------------------


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


def save_commands(rows: list[tuple[Any, ...]], conn: sqlite3.Connection) -> None:
    conn.executemany(_UPSERT, rows)


def select_command(command_id: str, conn: sqlite3.Connection) -> CommandRecord | None:
    row = conn.execute(f"SELECT {_COLUMNS} FROM commands WHERE id = ?", (command_id,)).fetchone()
    return None if row is None else record_from_row(row)


def select_commands(
    twin_id: int,
    state: str | None,
    name: str | None,
    device: str | None,
    limit: int,
    conn: sqlite3.Connection,
) -> list[CommandRecord]:
    """The twin's commands, newest first."""
    sql = f"SELECT {_COLUMNS} FROM commands WHERE twin_id = ?"
    params: list[Any] = [twin_id]
    for column, value in (("state", state), ("name", name), ("device", device)):
        if value is not None:
            sql += f" AND {column} = ?"
            params.append(value)
    sql += " ORDER BY created_ns DESC, id LIMIT ?"
    params.append(limit)
    return [record_from_row(r) for r in conn.execute(sql, params)]


def select_open_commands(conn: sqlite3.Connection) -> list[CommandRecord]:
    rows = conn.execute(
        f"SELECT {_COLUMNS} FROM commands WHERE state IN ('pending', 'delivered') "
        "ORDER BY created_ns"
    )
    return [record_from_row(r) for r in rows]


def delete_commands_of(twin_ids: list[int], conn: sqlite3.Connection) -> None:
    conn.executemany("DELETE FROM commands WHERE twin_id = ?", [(i,) for i in twin_ids])


class WriteBehind:
    """Command state changes, written behind the caller: each change is in the log within one
    group commit, and changes made while a commit runs share the next one (one upsert per
    command, however often its state changed). `sync` waits until everything saved so far is
    committed.

    A write that fails (a full disk) keeps its changes for the next one (unless newer ones
    of the same command came meanwhile) and fails the `sync` calls waiting for it; it is
    tried again with the next `save` or `sync`, not in a loop against a disk that is full."""

    def __init__(self, write: Write) -> None:
        self._write = write
        self._dirty: dict[str, CommandRecord] = {}
        self._waiters: list[asyncio.Future[None]] = []
        self._task: asyncio.Task[None] | None = None
        self.closed = False

    def save(self, record: CommandRecord) -> None:
        if self.closed:  # shutting down: the history file is closing; open commands reload
            return
        self._dirty[record.id] = record
        self._kick()

    async def sync(self) -> None:
        if self._task is None and not self._dirty:
            return
        waiter: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self._waiters.append(waiter)
        self._kick()
        await waiter

    def _kick(self) -> None:
        if self._task is None:
            self._task = asyncio.create_task(self._run(), name="command-log-writer")

    async def close(self) -> None:
        """Write what is unsaved, then take no more (shutting down). Best effort: on a disk
        that refuses it, open commands reload from what the log last took."""
        try:
            await self.sync()
        except StorageError:
            log.warning("%d command change(s) not written at shutdown: storage failed",
                        len(self._dirty), extra={"event": "command_log_failed"})  # fmt: skip
        self.closed = True

    async def _run(self) -> None:
        try:
            while self._dirty or self._waiters:
                taken = self._dirty
                self._dirty = {}
                waiters, self._waiters = self._waiters, []
                if not taken:
                    _settle(waiters, None)
                    continue
                try:
                    await self._write(
                        partial(save_commands, [command_row(r) for r in taken.values()])
                    )
                except Exception as err:
                    if not isinstance(err, StorageError):  # the store logged that one
                        log.exception("writing the command log failed",
                                      extra={"event": "command_log_failed"})  # fmt: skip
                    for command_id, record in taken.items():  # newer changes win
                        self._dirty.setdefault(command_id, record)
                    _settle([*waiters, *self._waiters], err)
                    self._waiters = []
                    return
                _settle(waiters, None)
        finally:
            self._task = None


def _settle(waiters: Iterable[asyncio.Future[None]], error: BaseException | None) -> None:
    for waiter in waiters:
        if waiter.done():
            continue
        if error is None:
            waiter.set_result(None)
        else:
            waiter.set_exception(error)


def _json(value: Any) -> str:
    return orjson.dumps(value).decode()
