"""Command state transitions, the write-behind log, and a device's property state."""

from __future__ import annotations

import asyncio
import base64
import time
from typing import Any

import pytest

from twinlink.commands.write_behind import WriteBehind
from twinlink.domain.commands import CommandRecord, iso_time, new_command_id
from twinlink.domain.doctime import human_time
from twinlink.domain.properties import DeviceProperties
from twinlink.store.sqlite.commands import command_row, record_from_row
from twinlink.store.sqlite.properties import property_rows


def _record(**changes: Any) -> CommandRecord:
    fields: dict[str, Any] = dict(
        id=new_command_id(), twin_id=1, device_id=2, device="rig", name="go", args={"x": 1},
        state="pending", queued=False, sent_by="ann", created_ns=100, expires_ns=200,
    )  # fmt: skip
    fields.update(changes)
    return CommandRecord(**fields)


def test_pending_delivered_succeeded() -> None:
    r = _record()
    assert r.deliver(110) and r.state == "delivered" and r.delivered_ns == 110
    assert not r.deliver(111)  # a second `delivered` changes nothing
    assert r.finish("succeeded", {"ok": True}, None, 120)
    assert (r.state, r.result, r.finished_ns, r.is_open) == ("succeeded", {"ok": True}, 120, False)
    assert not r.finish("failed", None, "again", 130)  # a second result is ignored
    assert not r.expire(300) and r.state == "succeeded"


def test_a_result_without_delivered_implies_delivery() -> None:
    r = _record()
    assert r.finish("failed", None, "jammed", 150)
    assert (r.state, r.error, r.delivered_ns) == ("failed", "jammed", 150)


def test_expiry_and_a_late_result() -> None:
    r = _record()
    assert r.deliver(110) and r.expire(200)
    assert (r.state, r.finished_ns) == ("expired", 200)
    assert r.finish("succeeded", 7, None, 250)  # recorded ...
    assert (r.state, r.late_status, r.result, r.finished_ns) == ("expired", "succeeded", 7, 200)
    assert not r.finish("failed", None, "x", 260)  # ... once
    assert not r.deliver(270)


def test_offline_failure_and_bad_status() -> None:
    r = _record()
    assert r.fail("device offline", 101) and r.state == "failed"
    assert not r.fail("again", 102)
    with pytest.raises(ValueError, match="status"):
        _record().finish("done", None, None, 1)


def test_ids_are_short_and_distinct() -> None:
    ids = {new_command_id() for _ in range(1000)}
    assert len(ids) == 1000 and all(len(i) == 16 for i in ids)


def test_ids_begin_with_the_millisecond_they_were_made() -> None:
    before = time.time_ns() // 1_000_000
    made = new_command_id()
    after = time.time_ns() // 1_000_000
    assert before <= int.from_bytes(base64.urlsafe_b64decode(made)[:6], "big") <= after


@pytest.mark.parametrize(
    "ns", [1_732_200_000_123_000_000, 0, 4_102_444_799_999_000_000, 1_732_200_000_000_000_000]
)
def test_times_are_shown_as_the_rest_of_the_api_shows_them(ns: int) -> None:
    assert iso_time(ns) == human_time(ns)
    assert iso_time(ns + 999_999) == human_time(ns)  # milliseconds, truncated


def test_rows_round_trip() -> None:
    r = _record(queued=True, result=[1, "a"], error="e", late_status="failed", delivered_ns=5)
    assert record_from_row(command_row(r)) == r
    assert record_from_row(command_row(_record())).result is None


async def test_write_behind_coalesces_and_sync_waits_for_the_commit() -> None:
    commits: list[list[tuple[str, str]]] = []
    gate, started = asyncio.Event(), asyncio.Event()

    async def save(records: list[CommandRecord]) -> None:
        started.set()
        await gate.wait()
        commits.append([(r.id, r.state) for r in records])

    log = WriteBehind(save)
    a, b = _record(), _record()
    log.save(a)
    log.save(b)
    a.deliver(1)
    log.save(a)  # the same command twice before the commit: one row, its latest state
    synced = asyncio.create_task(log.sync())
    await started.wait()  # the commit is under way, held at the gate
    assert not synced.done()
    gate.set()
    await synced
    assert sorted(commits[0]) == sorted([(a.id, "delivered"), (b.id, "pending")])
    await log.sync()  # nothing new: returns at once
    assert len(commits) == 1


def test_device_properties_delta_and_versions() -> None:
    p = DeviceProperties(device_id=1, twin_id=2, device_created_ns=3)
    assert p.set_desired({"rate": 50, "mode": "eco"}, 10) == ["rate", "mode"] and p.version == 1
    assert p.delta() == {"rate": 50, "mode": "eco"}
    p.set_reported({"rate": 50.0, "mode": "fast"}, 20)
    assert p.delta() == {"mode": "eco"}  # 50.0 reported is 50 desired
    assert p.set_desired({"rate": 50}, 30) == [] and p.version == 1  # unchanged
    assert p.set_desired({"mode": None, "gone": None}, 40) == ["mode"] and p.version == 2
    assert p.delta() == {}
    view = p.view()
    assert view["desired"] == {"rate": {"value": 50, "time": "1970-01-01T00:00:00.000Z"}}
    assert view["reported"]["mode"]["value"] == "fast" and view["version"] == 2
    assert property_rows(p, ["mode"]) == [(1, "mode", '"fast"', 20, None, None)]
