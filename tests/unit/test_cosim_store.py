"""The co-simulations' table through the CosimStore protocol: a record stored with its own id
and read back whole (its JSON fields too), saved as its run goes, listed newest first, deleted,
and the runs a stopped server left `running` failed (only its own nodes' when named).

Runs on SQLite here and on PostgreSQL in tests/integration/test_cosim_store_postgres.py."""

from __future__ import annotations

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.domain.cosims import CosimRecord


def _cosim(name: str = "msd", node: str | None = None) -> CosimRecord:
    return CosimRecord(
        id=0, name=name, owner_id=None, twin="rig", prefix="sim.", stream="cosim",
        mode="batch", factor=1.0, state="created", format="maestro",
        document="upload/msd.json", fmus={"mass.fmu": {"path": "upload/mass.fmu",
                                                       "source": "upload"}},
        system={"source": "maestro", "loops": [], "end_time": 1.5}, created_ns=5, node=node,
    )  # fmt: skip


async def test_a_cosim_is_stored_and_read_back_whole(stores: Stores) -> None:
    store = stores.metadata
    first = await store.create_cosim(_cosim())
    second = await store.create_cosim(_cosim("other"))
    assert 0 < first.id < second.id
    got = await store.get_cosim(first.id)
    assert got == first
    assert got is not None and got.fmus["mass.fmu"]["path"] == "upload/mass.fmu"
    assert got.system["end_time"] == 1.5 and got.sim_time is None
    assert await store.get_cosim(second.id + 100) is None


async def test_a_saved_run_reads_back_and_lists_newest_first(stores: Stores) -> None:
    store = stores.metadata
    a, b = await store.create_cosim(_cosim()), await store.create_cosim(_cosim())
    a.state, a.progress, a.sim_time, a.rows = "finished", 1.0, 1.5, 151
    a.columns = ["time", "{msd1}.m1.x1"]
    a.started_ns, a.ended_ns, a.message, a.node = 10, 20, "", "host:1:x"
    await store.save_cosim(a)
    assert await store.get_cosim(a.id) == a
    assert [r.id for r in await store.list_cosims()] == [b.id, a.id]
    assert [r.id for r in await store.list_cosims("finished")] == [a.id]
    assert await store.delete_cosim(a.id)
    assert not await store.delete_cosim(a.id)
    assert [r.id for r in await store.list_cosims()] == [b.id]


async def test_running_cosims_left_by_a_stop_are_failed(stores: Stores) -> None:
    store = stores.metadata
    mine, other, done = [await store.create_cosim(_cosim(node=n)) for n in ("a", "b", "a")]
    for record, state in ((mine, "running"), (other, "running"), (done, "finished")):
        record.state = state
        await store.save_cosim(record)
    failed = await store.fail_running_cosims(["a"], "the server stopped", 99)
    assert [r.id for r in failed] == [mine.id]
    got = await store.get_cosim(mine.id)
    assert got is not None and (got.state, got.message, got.ended_ns) == (
        "failed", "the server stopped", 99)  # fmt: skip
    assert [r.id for r in await store.fail_running_cosims(None, "gone", 100)] == [other.id]
    done_now = await store.get_cosim(done.id)
    assert done_now is not None and done_now.state == "finished"
