"""The tests of the caches in front of the metadata store (tests/unit/test_caches.py) on
PostgreSQL, against a real server (_postgres.py): the same counting store, around a
PostgresMetadataStore."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.unit import test_caches
from tests.unit.test_caches import CountingStore, private_twin, user
from twinlink.auth.rights import Principal
from twinlink.domain.errors import NotFoundError
from twinlink.registry.service import RegistryService
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata import PostgresMetadataStore

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]


@pytest.fixture
async def store(postgres_dsn: str) -> AsyncIterator[CountingStore]:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        yield CountingStore(PostgresMetadataStore(db))  # type: ignore[arg-type]
    finally:
        await db.close()


async def test_a_new_user_with_a_deleted_user_s_id_has_none_of_its_roles(
    store: CountingStore,
) -> None:
    """In place of the SQLite test of that name: PostgreSQL never gives a deleted user's id
    again, so a new user cannot inherit its cached roles to begin with."""
    registry = RegistryService(store, "http://x")  # type: ignore[arg-type]
    alice = await user(store, "alice")
    bob = await user(store, "bob", created_ns=1)
    await private_twin(store, "rig", alice)
    await registry.set_role(Principal(alice), "rig", "bob", "editor")
    await registry.require_twin(Principal(bob), "rig")  # bob's role is cached
    assert await store.store.delete_user(bob.id)  # nothing tells the registry
    carol = await user(store, "carol", created_ns=2)
    assert carol.id > bob.id
    with pytest.raises(NotFoundError):
        await registry.require_twin(Principal(carol), "rig")


rerun_on_postgres(test_caches, globals())
