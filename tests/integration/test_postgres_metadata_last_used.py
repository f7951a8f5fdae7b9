"""The tests of "last used" times written behind (tests/unit/test_last_used.py) on
PostgreSQL, against a real server (_postgres.py): the same failing-disk store, around a
PostgresMetadataStore."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.unit import test_last_used
from tests.unit.test_last_used import FullDisk
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata import PostgresMetadataStore

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]


@pytest.fixture
async def store(postgres_dsn: str) -> AsyncIterator[FullDisk]:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        yield FullDisk(PostgresMetadataStore(db))  # type: ignore[arg-type]
    finally:
        await db.close()


rerun_on_postgres(test_last_used, globals())
