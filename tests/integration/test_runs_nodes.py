"""Two nodes' run services on one shared store, with real processes: a run whose runner tags
only one node has is claimed and run by that node, and a run one node runs is cancelled from
the other (its process group stopped by the node that runs it).

The services are the server's own (deploy/runs.py) on one SQLite store, as two nodes share
PostgreSQL; tests/integration/test_runs.py runs them in a real server."""

from __future__ import annotations

import asyncio
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path

import psutil
import pytest

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthService
from twinlink.deploy.runner import Limits
from twinlink.deploy.runs import RunService, RunSettings, RunTarget
from twinlink.domain.runs import RunRecord

pytestmark = pytest.mark.integration

SCRIPT = 'sleep 600 &\necho "child $!"\nwhile [ ! -e go ]; do sleep 0.05; done\n'


def _target(tags: list[str], owner_id: int) -> RunTarget:
    async def prepare(work: Path) -> None:
        (work / "lifecycle").mkdir(parents=True, exist_ok=True)
        (work / "lifecycle" / "analyze").write_text(SCRIPT)

    return RunTarget(
        deployment_id=1, deployment="rig", twin="rig", owner_id=owner_id, prepare=prepare,
        runner_tags=tags,
    )  # fmt: skip


def _node(stores: Stores, root: Path, name: str, tags: frozenset[str]) -> RunService:
    settings = RunSettings(root / name, "http://127.0.0.1:1", name, tags, "admins",
                           Limits(60, 0), shared=True,
                           folders=root / f"{name}-deployments")  # fmt: skip
    return RunService(stores.metadata, AuthService(stores.metadata, 3600), settings)


@pytest.fixture
async def nodes(
    stores: Stores, tmp_path: Path
) -> AsyncIterator[tuple[RunService, RunService, Principal]]:
    admin = await stores.metadata.create_user("admin", None, True, [], 1)
    plain = _node(stores, tmp_path, "node-a", frozenset())
    gpu = _node(stores, tmp_path, "node-b", frozenset({"gpu"}))
    owner = admin.id
    for node in (plain, gpu):
        node.target_loader = lambda run: _loaded(run, owner)
        await node.open()
    try:
        yield plain, gpu, Principal(admin)
    finally:
        for node in (plain, gpu):
            await node.close()


async def _loaded(run: RunRecord, owner_id: int) -> RunTarget:
    return _target(run.runner_tags, owner_id)


async def _until(check: Callable[[], Awaitable[bool]], what: str) -> None:
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        if await check():
            return
        await asyncio.sleep(0.05)  # polling the real state
    raise AssertionError(f"timed out waiting for {what}")


def _alive(pid: int) -> bool:
    try:
        return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _log(node: RunService, run_id: int) -> str:
    path = node.settings.root / f"{run_id}.log"
    return path.read_text() if path.exists() else ""


async def test_a_tagged_run_is_claimed_and_run_by_the_node_with_the_tags(
    nodes: tuple[RunService, RunService, Principal],
) -> None:
    plain, gpu, admin = nodes
    owner = admin.user.id if admin.user else 0
    run = await plain.start(admin, _target(["gpu"], owner), "analyze")
    assert run.node is None and run.state == "queued"

    async def running() -> bool:
        return (await plain.get(run.id)).state == "running" and "child" in _log(gpu, run.id)

    await _until(running, "the gpu node to claim and start the run")
    assert (await plain.get(run.id)).node == "node-b"
    assert _log(plain, run.id) == ""  # node-a never ran it
    with pytest.raises(TimeoutError):  # waiting is bounded, and leaves the run running
        await plain.wait(run.id, 0.2)
    assert (await plain.get(run.id)).state == "running"
    (gpu.settings.folder(1) / "go").touch()  # the deployment's folder on the node of its run
    # Either node sees its end: the one running it awaits it, the other looks at the store.
    assert (await gpu.wait(run.id, 60)).state == "succeeded"
    assert (await plain.wait(run.id, 60)).state == "succeeded"
    assert not (plain.settings.folder(1)).exists()  # each node has its own folders


async def test_a_run_is_cancelled_from_another_node(
    nodes: tuple[RunService, RunService, Principal],
) -> None:
    plain, gpu, admin = nodes
    owner = admin.user.id if admin.user else 0
    run = await plain.start(admin, _target([], owner), "analyze")

    async def started() -> bool:
        return "child " in _log(plain, run.id)

    await _until(started, "the run to start on node-a")
    child = int(_log(plain, run.id).split("child ")[1].split()[0])
    cancelled = await gpu.cancel(admin, run.id)  # node-b does not run it
    assert cancelled.state == "cancelled"

    async def stopped() -> bool:
        return "[twinlink] cancelled" in _log(plain, run.id) and not _alive(child)

    await _until(stopped, "node-a to stop the run another node cancelled")
    assert (await plain.get(run.id)).state == "cancelled"
