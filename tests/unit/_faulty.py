"""A SQLite connection that fails the Nth statement the way a full (or failing) disk does,
for the tests of what the stores do then. Everything else goes to the real connection."""

from __future__ import annotations

import sqlite3
from pathlib import Path
from typing import Any

import pytest

from twinlink.store.sqlite.history import writer as writer_module


def disk_error(code: int = sqlite3.SQLITE_FULL) -> sqlite3.OperationalError:
    """The error sqlite3 raises for `code` (SQLITE_FULL, SQLITE_IOERR_WRITE, ...)."""
    text = "database or disk is full" if code == sqlite3.SQLITE_FULL else "disk I/O error"
    err = sqlite3.OperationalError(text)
    err.sqlite_errorcode = code
    err.sqlite_errorname = "SQLITE_FULL" if code == sqlite3.SQLITE_FULL else "SQLITE_IOERR"
    return err


class FaultyConnection:
    """Counts statements once `arm`ed and fails number `at` with `code`. SQLite answers a
    full disk at COMMIT by rolling the transaction back itself; with `whole`, a failure
    anywhere does that (a full disk while spilling pages), else only the statement fails."""

    def __init__(self, conn: sqlite3.Connection) -> None:
        self.conn = conn
        self.at = 0
        self.count = 0
        self.whole = False
        self.code = sqlite3.SQLITE_FULL
        self.fired = False
        self.statements: list[str] = []

    def arm(self, at: int, whole: bool = False, code: int = sqlite3.SQLITE_FULL) -> None:
        self.at, self.count, self.whole, self.code, self.fired = at, 0, whole, code, False
        self.statements = []

    def disarm(self) -> None:
        self.at = 0

    @property
    def in_transaction(self) -> bool:
        return self.conn.in_transaction

    def execute(self, sql: str, *args: Any) -> sqlite3.Cursor:
        self._tick(sql)
        return self.conn.execute(sql, *args)

    def executemany(self, sql: str, rows: Any) -> sqlite3.Cursor:
        self._tick(sql)
        return self.conn.executemany(sql, rows)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.conn, name)

    def _tick(self, sql: str) -> None:
        if not self.at:
            return
        self.count += 1
        self.statements.append(sql.split(" (")[0])
        if self.count != self.at:
            return
        self.fired = True
        if (self.whole or sql == "COMMIT") and self.conn.in_transaction:
            self.conn.execute("ROLLBACK")
        raise disk_error(self.code)


def wrap_writer_connections(monkeypatch: pytest.MonkeyPatch) -> list[FaultyConnection]:
    """Make the history writer open FaultyConnections (disarmed); the list gets each one."""
    made: list[FaultyConnection] = []
    real = writer_module.open_connection

    def connect(path: Path, synchronous: str) -> Any:
        made.append(FaultyConnection(real(path, synchronous)))
        return made[-1]

    monkeypatch.setattr(writer_module, "open_connection", connect)
    return made
