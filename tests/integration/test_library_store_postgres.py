"""tests/unit/test_library_store.py's tests on PostgreSQL."""

from __future__ import annotations

import asyncio
import time

import asyncpg
import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres import stores as stores
from tests.unit import test_library_store
from tests.unit._storage import Stores

pytestmark = pytest.mark.integration

rerun_on_postgres(test_library_store, globals())


async def test_the_blob_lock_is_held_by_one_node_at_a_time(
    stores: Stores, postgres_dsn: str
) -> None:
    """A sweep on one node and a push's last step on another take turns (SQLite has one
    process, so only PostgreSQL's lock is shared)."""
    store = stores.metadata
    entered: list[str] = []

    async def second() -> None:
        async with store.blob_lock():
            entered.append("second")

    waiting = "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND NOT granted"
    async with store.blob_lock():
        task = asyncio.create_task(second())
        conn = await asyncpg.connect(postgres_dsn)
        try:
            deadline = time.monotonic() + 20
            while not await conn.fetchval(waiting):  # the second is queued on the lock
                assert time.monotonic() < deadline, "the second never waited for the lock"
                await asyncio.sleep(0.01)  # polling the database's state, with a deadline
        finally:
            await conn.close()
        assert entered == [] and not task.done()
    await task
    assert entered == ["second"]
