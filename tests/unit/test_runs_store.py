"""The runs' table through the RunStore protocol: a run stored queued with its id, claimed by
one node of several, started only from queued, ended once, and the runs a stopped server
left failed (not those still waiting for a node with their tags).

Runs on SQLite here and on PostgreSQL in tests/integration/test_runs_store_postgres.py."""

from __future__ import annotations

import asyncio

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.domain.runs import RunRecord


def _run(
    phase: str = "analyze", node: str | None = "node-a", tags: list[str] | None = None
) -> RunRecord:
    return RunRecord(
        id=0, deployment_id=7, deployment="rig", twin="rig", phase=phase, state="queued",
        started_by=None, created_ns=1, timeout_s=60, memory_mb=512, runner_tags=tags or [],
        node=node,
    )  # fmt: skip


async def test_a_run_is_stored_and_read_back_with_its_own_id(stores: Stores) -> None:
    store = stores.metadata
    first = await store.create_run(_run(tags=["gpu", "lab"]))
    second = await store.create_run(_run())
    assert 0 < first.id < second.id
    got = await store.get_run(first.id)
    assert got is not None
    assert (got.state, got.phase, got.node) == ("queued", "analyze", "node-a")
    assert got.runner_tags == ["gpu", "lab"]
    assert (got.timeout_s, got.memory_mb, got.deployment_id) == (60, 512, 7)
    assert await store.get_run(second.id + 100) is None


async def test_of_two_nodes_claiming_a_queued_run_exactly_one_gets_it(stores: Stores) -> None:
    store = stores.metadata
    run = await store.create_run(_run(node=None, tags=["gpu"]))
    won = await asyncio.gather(store.claim_run(run.id, "node-a"), store.claim_run(run.id, "node-b"))
    assert sorted(won) == [False, True]
    got = await store.get_run(run.id)
    assert got is not None and got.node == ("node-a" if won[0] else "node-b")
    assert not await store.claim_run(run.id, "node-c")  # taken stays taken
    mine = await store.create_run(_run(node="node-a"))  # queued by a node for itself
    assert not await store.claim_run(mine.id, "node-b")


async def test_a_run_starts_only_from_queued_and_ends_once(stores: Stores) -> None:
    store = stores.metadata
    run = await store.create_run(_run())
    assert await store.end_run(run.id, "cancelled", None, "cancelled", 5)
    assert not await store.mark_run_running(run.id, 123, 6)  # cancelled before it started
    other = await store.create_run(_run())
    assert await store.mark_run_running(other.id, 123, 6)
    await store.set_run_token(other.id, 42)
    assert await store.end_run(other.id, "failed", -9, "killed by signal SIGKILL", 9)
    assert not await store.end_run(other.id, "succeeded", 0, None, 10)
    got = await store.get_run(other.id)
    assert got is not None
    assert (got.state, got.exit_code, got.error, got.pid, got.token_id) == (
        "failed",
        -9,
        "killed by signal SIGKILL",
        123,
        42,
    )
    assert (got.started_ns, got.ended_ns) == (6, 9)


async def test_runs_are_listed_newest_first_by_deployment_and_state(stores: Stores) -> None:
    store = stores.metadata
    a, b, c = [await store.create_run(_run()) for _ in range(3)]
    other = _run()
    other.deployment_id = 8
    d = await store.create_run(other)
    await store.end_run(b.id, "succeeded", 0, None, 5)
    assert [r.id for r in await store.list_runs(deployment_id=7)] == [c.id, b.id, a.id]
    assert [r.id for r in await store.list_runs()] == [d.id, c.id, b.id, a.id]
    queued = await store.list_runs(states=("queued",), deployment_id=7)
    assert [r.id for r in queued] == [c.id, a.id]
    assert [r.id for r in await store.list_runs(limit=1, before_id=c.id)] == [b.id]


async def test_a_stopped_servers_runs_are_failed_but_unclaimed_ones_wait(stores: Stores) -> None:
    store = stores.metadata
    running = await store.create_run(_run())
    await store.mark_run_running(running.id, 1, 2)
    await store.set_run_token(running.id, 11)
    queued_here = await store.create_run(_run())
    waiting = await store.create_run(_run(node=None, tags=["gpu"]))
    done = await store.create_run(_run())
    await store.end_run(done.id, "succeeded", 0, None, 3)
    failed = await store.fail_interrupted_runs(None, "the server stopped during the run", 9)
    assert sorted(r.id for r in failed) == [running.id, queued_here.id]
    assert {r.id: r.token_id for r in failed}[running.id] == 11
    for run_id in (running.id, queued_here.id):
        got = await store.get_run(run_id)
        assert got is not None and (got.state, got.error, got.ended_ns) == (
            "failed",
            "the server stopped during the run",
            9,
        )
    left = await store.get_run(waiting.id)
    assert left is not None and left.state == "queued"
    kept = await store.get_run(done.id)
    assert kept is not None and kept.state == "succeeded"
    on_b = await store.create_run(_run(node="host-b:1:x"))
    assert [r.id for r in await store.fail_interrupted_runs("host-a:%", "gone", 10)] == []
    assert [r.id for r in await store.fail_interrupted_runs("host-b:%", "gone", 10)] == [on_b.id]
