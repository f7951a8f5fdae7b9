"""The device SDK's commands and properties, and its synchronous API, against FakeServer
(tests/unit/test_edge_device.py), an in-process fake of the device WebSocket."""

from __future__ import annotations

import asyncio
import queue
import threading

import pytest

from tests.unit.test_edge_device import TIMEOUT, FakeServer, Msg, device
from tests.unit.test_edge_device import fake as fake  # the fixture
from twinlink_edge import Device, ReportError


async def test_commands_run_their_handlers_and_report_results(fake: FakeServer) -> None:
    calls = []
    async with device(fake) as dev:

        @dev.on_command("set_k")
        def set_k(args: Msg) -> Msg:
            calls.append(args)
            return {"k": args["k"] * 2}

        @dev.on_command("boom")
        async def boom(args: Msg) -> None:
            raise RuntimeError("it broke")

        assert await dev.wait_connected(TIMEOUT)
        fake.push({"type": "command", "id": "c1", "name": "set_k", "args": {"k": 2}})
        fake.push({"type": "command", "id": "c2", "name": "boom", "args": {}})
        fake.push({"type": "command", "id": "c3", "name": "nope"})
        await fake.until(lambda f: len(f.of_type("result")) == 3)
        fake.push({"type": "command", "id": "c1", "name": "set_k", "args": {"k": 2}})  # again
        await fake.until(lambda f: len(f.of_type("result")) == 4)
    results = {r["id"]: r for r in fake.of_type("result")}
    assert results["c1"] == {
        "type": "result",
        "id": "c1",
        "status": "succeeded",
        "result": {"k": 4},
    }
    assert (results["c2"]["status"], results["c2"]["error"]) == ("failed", "it broke")
    assert results["c3"]["error"] == "no handler for command 'nope'"
    assert calls == [{"k": 2}]  # a command that comes again is answered, not run again
    order = [(m["type"], m["id"]) for m in fake.received if m["type"] in ("delivered", "result")]
    for cid in ("c1", "c2", "c3"):
        assert order.index(("delivered", cid)) < order.index(("result", cid))


async def test_close_waits_until_the_server_has_the_command_answers(fake: FakeServer) -> None:
    async with device(fake) as dev:

        @dev.on_command("go")
        async def go(args: Msg) -> str:
            return "gone"

        assert await dev.wait_connected(TIMEOUT)
        fake.push({"type": "command", "id": "g", "name": "go", "args": {}})

        async def result_queued() -> None:
            while dev._dispatcher._results.get("g") is None:
                await asyncio.sleep(0.001)

        await asyncio.wait_for(result_queued(), TIMEOUT)
        # ... and leave at once, maybe before the connection's sender had a turn to send it.
    [result] = fake.of_type("result")
    assert (result["id"], result["result"]) == ("g", "gone")
    assert [m["type"] for m in fake.received] == ["delivered", "result", "ping"]


async def test_a_round_trip_lost_with_its_connection_is_made_again(fake: FakeServer) -> None:
    async with device(fake) as dev:
        assert await dev.wait_connected(TIMEOUT)
        fake.answer_pings = False  # a ping the server never answers: lost with its connection
        trip = asyncio.ensure_future(dev._round_trip(TIMEOUT))
        await fake.until(lambda f: len(f.of_type("ping")) == 1)
        fake.answer_pings = True
        fake.drop()
        await asyncio.wait_for(trip, TIMEOUT)  # its ping went out again on the next connection
        assert dev.connections == 2 and len(fake.of_type("ping")) == 2


async def test_desired_and_reported_properties(fake: FakeServer) -> None:
    fake.welcome_extra = {"desired": {"K": 0.85}, "desired_version": 3}
    fake.reported_extra = {"desired": {"mode": "fast"}}
    seen: asyncio.Queue[Msg] = asyncio.Queue()
    dev = device(fake)

    @dev.on_desired
    async def changed(delta: Msg) -> None:
        await seen.put(delta)

    async with dev:
        assert await asyncio.wait_for(seen.get(), TIMEOUT) == {"K": 0.85}
        assert (dev.desired, dev.desired_version) == ({"K": 0.85}, 3)
        fake.push({"type": "desired", "properties": {"K": 0.85, "mode": "fast"}, "version": 4})
        assert await asyncio.wait_for(seen.get(), TIMEOUT) == {"K": 0.85, "mode": "fast"}
        assert (dev.desired, dev.desired_version) == ({"K": 0.85, "mode": "fast"}, 4)
        # The ack of a report says what is still to do; nothing new: no call.
        assert await dev.report({"K": 0.85}, timeout=TIMEOUT) == 1
        assert dev.desired == {"mode": "fast"} and seen.empty()
        assert await dev.report({"mode": "fast"}, timeout=TIMEOUT) == 2
        assert dev.reported == {"K": 0.85, "mode": "fast"}
    reports = fake.of_type("reported")
    assert [m["properties"] for m in reports] == [{"K": 0.85}, {"mode": "fast"}]
    assert reports[0]["id"] != reports[1]["id"]


async def test_reports_are_matched_by_id_resent_and_may_be_refused(fake: FakeServer) -> None:
    fake.answer_reports = False
    async with device(fake) as dev:
        first = asyncio.ensure_future(dev.report({"a": 1}))
        second = asyncio.ensure_future(dev.report({"b": 2}))
        await fake.until(lambda f: len(f.of_type("reported")) == 2)
        fake.drop()  # unanswered reports go out again on the next connection
        await fake.until(lambda f: len(f.of_type("reported")) == 4)
        ids = [m["id"] for m in fake.of_type("reported")]
        assert ids[2:] == ids[:2]
        fake.push({"type": "error", "op": "reported", "id": ids[0], "message": "a: not allowed"})
        fake.push({"type": "reported_ack", "id": ids[1], "version": 9, "desired": {}})
        with pytest.raises(ReportError, match="a: not allowed"):
            await asyncio.wait_for(first, TIMEOUT)
        assert await asyncio.wait_for(second, TIMEOUT) == 9
        assert dev.reported_version == 9


def test_the_sync_device_blocks_when_full_and_runs_handlers_in_threads(fake: FakeServer) -> None:
    fake.auto_ack = False
    with Device(fake.url, fake.token, batch_size=10, max_buffered_samples=20) as dev:

        @dev.on_command("report")
        def report(args: Msg) -> int | None:
            return dev.report(args, timeout=TIMEOUT)  # a blocking call from a handler

        for i in range(20):
            dev.add({"i": i})
        adder = threading.Thread(target=dev.add, args=({"i": 20},))
        adder.start()
        fake.wait(lambda f: len(f.batches()) == 2)
        assert adder.is_alive()
        fake.auto_ack = True
        fake.ack(*[b["seq"] for b in fake.batches()])
        adder.join(TIMEOUT)
        assert not adder.is_alive()
        fake.push({"type": "command", "id": "r", "name": "report", "args": {"K": 1}})
        fake.wait(lambda f: len(f.of_type("result")) == 1)
        dev.flush(TIMEOUT)
        assert dev.acked_samples == 21 and dev.reported == {"K": 1}
    assert fake.of_type("result")[0]["result"] == 1


def test_a_desired_handler_registered_late_hears_the_current_delta(fake: FakeServer) -> None:
    fake.welcome_extra = {"desired": {"K": 0.5}, "desired_version": 1}
    seen: queue.Queue[Msg] = queue.Queue()
    with Device(fake.url, fake.token) as dev:
        assert dev.wait_connected(TIMEOUT)
        dev.on_desired(seen.put)  # after the welcome
        assert seen.get(timeout=TIMEOUT) == {"K": 0.5}
        fake.push({"type": "desired", "properties": {"K": 0.6}, "version": 2})
        assert seen.get(timeout=TIMEOUT) == {"K": 0.6}
        assert dev.desired == {"K": 0.6}
