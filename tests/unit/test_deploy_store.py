"""The deployments' table through the DeploymentStore protocol: one live deployment per name,
ended ones kept beside it, the journal and sealed secrets written back.

Runs on SQLite here and on PostgreSQL in tests/integration/test_deployments_store_postgres.py."""

from __future__ import annotations

import pytest

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import ConflictError


def _record(name: str, state: str = "applying") -> DeploymentRecord:
    return DeploymentRecord(
        id=0, name=name, package="lib:common/twins/rig@sha256:" + "a" * 64,
        package_ref="rig@1.0.0", parameters={"zeta": 0.7}, state=state, twin=name,
        created_ns=1, updated_ns=1,
    )  # fmt: skip


async def test_a_deployment_is_stored_and_written_back(stores: Stores) -> None:
    store = stores.metadata
    made = await store.create_deployment(_record("rig"))
    assert made.id > 0
    made.journal.append({"type": "twin", "name": "rig", "spec": {"name": "rig"}})
    made.state, made.secrets, made.updated_ns = "created", b"\x00sealed\xff", 5
    await store.save_deployment(made)
    got = await store.get_deployment(made.id)
    assert got is not None
    assert got.journal == [{"type": "twin", "name": "rig", "spec": {"name": "rig"}}]
    assert (got.state, got.secrets, got.updated_ns) == ("created", b"\x00sealed\xff", 5)
    assert got.parameters == {"zeta": 0.7} and got.package_ref == "rig@1.0.0"
    assert got.resources()["twin"] == "rig"
    assert await store.get_deployment(made.id + 1000) is None


async def test_one_live_deployment_per_name(stores: Stores) -> None:
    store = stores.metadata
    first = await store.create_deployment(_record("rig"))
    with pytest.raises(ConflictError, match="exists already"):
        await store.create_deployment(_record("rig"))
    first.state = "failed"
    await store.save_deployment(first)
    second = await store.create_deployment(_record("rig", "created"))
    found = await store.find_deployment("rig")
    assert found is not None and found.id == second.id  # the live one, not the newest ended
    second.state = "terminated"
    await store.save_deployment(second)
    found = await store.find_deployment("rig")
    assert found is not None and found.id == second.id  # the newest ended one
    assert await store.find_deployment("other") is None


async def test_deployments_are_listed_newest_first_and_by_state(stores: Stores) -> None:
    store = stores.metadata
    a = await store.create_deployment(_record("a", "applying"))
    b = await store.create_deployment(_record("b", "running"))
    assert [r.id for r in await store.list_deployments()] == [b.id, a.id]
    assert [r.name for r in await store.list_deployments("applying")] == ["a"]
