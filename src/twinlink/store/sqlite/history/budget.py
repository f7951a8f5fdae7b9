"""What one read may cost: a deadline, a number of values, and a way to stop it from outside.

Every read of the history runs under a `ReadBudget`. SQLite checks it through a progress
handler (every few thousand VM steps), and the Python work checks it between pages, so a
read over its time, a read whose client went away and every read at shutdown stop within
one bounded step instead of running to the end.
"""

from __future__ import annotations

import sqlite3
import threading
import time
from dataclasses import dataclass, field

from twinlink.domain.history import (
    QueryTimeoutError,
    QueryTooLargeError,
    ReadBudgetError,
    ReadCancelledError,
)

# VM instructions between two looks at the budget: about a millisecond of SQLite work.
_PROGRESS_EVERY = 20_000


@dataclass(frozen=True, slots=True)
class ReadLimits:
    """The budget of each read (TWINLINK_HISTORY_QUERY_TIMEOUT_S and friends)."""

    timeout_s: float = 30.0  # a query answered in one piece (samples, aggregate, ...)
    export_timeout_s: float = 3600.0  # an export, from its first to its last byte
    max_values: int = 2_000_000  # values one answer may hold

    def query(self) -> ReadBudget:
        return ReadBudget(self.timeout_s, self.max_values, "TWINLINK_HISTORY_QUERY_TIMEOUT_S")

    def export(self) -> ReadBudget:
        return ReadBudget(
            self.export_timeout_s, self.max_values, "TWINLINK_HISTORY_EXPORT_TIMEOUT_S"
        )


@dataclass(slots=True, eq=False)  # compared and hashed by identity
class ReadBudget:
    timeout_s: float
    max_values: int
    setting: str = "TWINLINK_HISTORY_QUERY_TIMEOUT_S"  # named in the timeout message
    deadline: float = field(init=False)
    stopped: str | None = field(default=None, init=False)  # why, once stopped from outside
    _lock: threading.Lock = field(default_factory=threading.Lock, init=False, repr=False)
    _conns: list[sqlite3.Connection] = field(default_factory=list, init=False, repr=False)

    def __post_init__(self) -> None:
        self.deadline = time.monotonic() + self.timeout_s

    def check(self) -> None:
        """Raise when the read must stop (call between steps of Python work)."""
        if self.stopped is not None:
            raise ReadCancelledError(self.stopped)
        if time.monotonic() > self.deadline:
            raise QueryTimeoutError(
                f"the read took longer than {self.setting} ({self.timeout_s:g} s) allows: "
                "narrow `start`/`end` or name fewer `signals`"
            )

    def values(self, count: int, what: str) -> None:
        """Refuse an answer of `count` values when it is over the budget."""
        if count > self.max_values:
            raise QueryTooLargeError(
                f"{what} would hold {count:,} values; at most {self.max_values:,} are allowed "
                "(TWINLINK_HISTORY_QUERY_MAX_VALUES): narrow `start`/`end`, name fewer "
                "`signals`, or ask for less per signal"
            )

    def stop(self, why: str) -> None:
        """Stop the read from any thread: its running SQL is interrupted now, its Python
        work at the next check."""
        with self._lock:
            self.stopped = why
            conns = list(self._conns)
        for conn in conns:
            conn.interrupt()

    def attach(self, conn: sqlite3.Connection) -> None:
        """Let the budget stop SQL running on `conn` (until `detach`)."""
        with self._lock:
            self._conns.append(conn)
        conn.set_progress_handler(self._over, _PROGRESS_EVERY)

    def detach(self, conn: sqlite3.Connection) -> None:
        conn.set_progress_handler(None, 0)
        with self._lock:
            if conn in self._conns:
                self._conns.remove(conn)

    def _over(self) -> int:
        return 1 if self.stopped is not None or time.monotonic() > self.deadline else 0

    def explain(self, err: sqlite3.OperationalError) -> ReadBudgetError | None:
        """The budget error behind an interrupted statement (None when it was not ours)."""
        if "interrupt" not in str(err):
            return None
        try:
            self.check()
        except ReadBudgetError as over:
            return over
        return ReadCancelledError("the read was interrupted")
