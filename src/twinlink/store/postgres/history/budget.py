"""The budget of a read of PostgreSQL history: its time and the values its answer may hold,
the same limits and messages as the SQLite backend's (TWINLINK_HISTORY_QUERY_TIMEOUT_S and
friends). The time is the server's `statement_timeout` for the read's transaction (so the
server stops the work, not only the wait) and, for an export, a deadline over its pages."""

from __future__ import annotations

import time
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

import asyncpg

from twinlink.domain.history import QueryTimeoutError, QueryTooLargeError
from twinlink.store.postgres.db import Connection, PostgresDatabase


@dataclass(frozen=True, slots=True)
class ReadLimits:
    timeout_s: float = 30.0  # a query answered in one piece (samples, aggregate, ...)
    export_timeout_s: float = 3600.0  # an export, from its first to its last byte
    max_values: int = 2_000_000  # values one answer may hold

    def query(self) -> ReadBudget:
        return ReadBudget(self.timeout_s, self.max_values, "TWINLINK_HISTORY_QUERY_TIMEOUT_S")

    def export(self) -> ReadBudget:
        return ReadBudget(
            self.export_timeout_s, self.max_values, "TWINLINK_HISTORY_EXPORT_TIMEOUT_S"
        )


@dataclass(slots=True)
class ReadBudget:
    timeout_s: float
    max_values: int
    setting: str
    deadline: float = field(init=False)

    def __post_init__(self) -> None:
        self.deadline = time.monotonic() + self.timeout_s

    def timeout(self) -> QueryTimeoutError:
        return QueryTimeoutError(
            f"the read took longer than {self.setting} ({self.timeout_s:g} s) allows: "
            "narrow `start`/`end` or name fewer `signals`"
        )

    def check(self) -> None:
        if time.monotonic() > self.deadline:
            raise self.timeout()

    def values(self, count: int, what: str) -> None:
        """Refuse an answer of `count` values when it is over the budget."""
        if count > self.max_values:
            raise QueryTooLargeError(
                f"{what} would hold {count:,} values; at most {self.max_values:,} are allowed "
                "(TWINLINK_HISTORY_QUERY_MAX_VALUES): narrow `start`/`end`, name fewer "
                "`signals`, or ask for less per signal"
            )


@asynccontextmanager
async def reading(db: PostgresDatabase, budget: ReadBudget) -> AsyncIterator[Connection]:
    """A connection in a read-only transaction that the server stops at the budget's
    deadline (QueryTimeoutError)."""
    budget.check()
    left_ms = max(1, int((budget.deadline - time.monotonic()) * 1000))
    async with db.connection() as conn, conn.transaction(readonly=True):
        await conn.execute(f"SET LOCAL statement_timeout = {left_ms}")
        try:
            yield conn
        except asyncpg.QueryCanceledError as err:  # the timeout, not the server going away
            raise budget.timeout() from err
