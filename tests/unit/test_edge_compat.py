"""twinlink_edge.compat: the NTNU thesis's device code runs with only its import changed.
Runs against FakeServer (tests/unit/test_edge_device.py), an in-process fake server."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator

import pytest

import twinlink_edge.compat
import twinlink_edge.compat as digitalTwinPlt
from tests.unit.test_edge_device import TIMEOUT, FakeServer
from twinlink_edge.compat import Connect, Message


@pytest.fixture
def fake(monkeypatch: pytest.MonkeyPatch) -> Iterator[FakeServer]:
    with FakeServer() as server:
        monkeypatch.setenv("TWINLINK_URL", server.url)
        monkeypatch.setenv("TWINLINK_DEVICE_TOKEN", server.token)
        yield server


def command(cid: str, name: str, args: dict[str, object] | None = None) -> dict[str, object]:
    return {"type": "command", "id": cid, "name": name, "args": args or {}}


def test_the_thesis_listing_runs(fake: FakeServer) -> None:
    dtMessaging = Connect(device_id="fake-device", topic="0000")
    try:
        dtMessaging.add_to_message(name="Temperature", value=20)
        dtMessaging.add_to_message(name="Input_F_in", value=8)
        dtMessaging.send()
        dtMessaging.add_to_message(name="Input_F_in", value=9)  # updates; Temperature stays
        dtMessaging.send()
        dtMessaging.flush(TIMEOUT)
        fake.push(command("c1", "pause"))
        fake.wait(lambda f: len(f.of_type("result")) == 1)
        paused = []
        instruction = dtMessaging.receive()
        for _topic, partition_msg in instruction.items():
            for m in partition_msg:
                if m.value == b"pause":
                    paused.append(m)
    finally:
        dtMessaging.close()
    samples = [s for b in fake.batches() for s in b["samples"]]
    assert [s["values"] for s in samples] == [
        {"Temperature": 20, "Input_F_in": 8},
        {"Temperature": 20, "Input_F_in": 9},
    ]
    assert samples[0]["time"] <= samples[1]["time"] <= time.time_ns()
    assert list(instruction) == ["0000"] and len(paused) == 1
    assert (paused[0].topic, paused[0].partition, paused[0].offset) == ("0000", 0, 1)
    assert fake.of_type("result")[0]["status"] == "succeeded"


def test_the_module_import_form_and_a_pause_loop_that_does_not_spin(fake: FakeServer) -> None:
    dthub = digitalTwinPlt.Connect(device_id="tingenSAP", topic="demo", receiving_partition=1)
    calls = 0

    def receive() -> dict[str, list[Message]]:
        nonlocal calls
        calls += 1
        if calls == 5:  # the operator presses start while the device polls
            threading.Thread(target=fake.push, args=(command("s", "start"),)).start()
        return dthub.receive()

    try:
        assert dthub.topic == "demo"
        assert dthub.device.wait_connected(TIMEOUT)
        assert dthub.receive() == {}
        started = time.monotonic()
        waiting = True
        while waiting:  # the thesis's pause(): poll until `start`
            for _topic, msgs in receive().items():
                waiting = not any(m.value == b"start" for m in msgs)
        elapsed = time.monotonic() - started
    finally:
        dthub.close()
    # Calls 1 to 4 found nothing after an empty call: each waited (up to 50 ms) rather than
    # spinning; the loop ended on `start` after a handful of calls, not thousands.
    assert elapsed >= 4 * 0.04 and calls < 50


def test_receive_waits_only_after_an_empty_call_with_no_send_between(
    fake: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(twinlink_edge.compat, "IDLE_WAIT", TIMEOUT)
    conn = Connect(topic="demo")
    try:
        assert conn.device.wait_connected(TIMEOUT)
        conn.add_to_message("x", 1)
        started = time.monotonic()
        assert conn.receive() == {}  # the first call: at once
        conn.send()
        assert conn.receive() == {}  # a send since the last call: at once
        assert time.monotonic() - started < TIMEOUT / 2
        # Nothing sent, the last call empty: this one waits, and takes the command that comes.
        waiting = threading.Event()
        wait_for = conn._cond.wait_for

        def note_the_wait(predicate: Callable[[], bool], timeout: float | None = None) -> bool:
            waiting.set()
            return wait_for(predicate, timeout)

        monkeypatch.setattr(conn._cond, "wait_for", note_the_wait)

        def push_when_waiting() -> None:
            assert waiting.wait(TIMEOUT)
            fake.push(command("c", "stop", {"after": 2}))

        pusher = threading.Thread(target=push_when_waiting)
        pusher.start()
        got = conn.receive()
        pusher.join()
        [message] = got["demo"]
        assert json.loads(message.value) == {"name": "stop", "args": {"after": 2}}
        assert (message.name, message.args) == ("stop", {"after": 2})
        started = time.monotonic()
        assert conn.receive() == {}  # the last call returned data: at once
        assert time.monotonic() - started < TIMEOUT / 2
        assert conn.receive(timeout_ms=0) == {}
    finally:
        conn.close()


def test_url_and_token_come_from_the_environment_or_arguments(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.delenv("TWINLINK_URL", raising=False)
    monkeypatch.delenv("TWINLINK_DEVICE_TOKEN", raising=False)
    with pytest.raises(ValueError, match="TWINLINK_URL"):
        Connect(device_id="d", topic="t")
    with FakeServer() as fake, Connect(url=fake.url, token=fake.token, topic="t") as conn:
        conn.add_to_message("x", 1)
        conn.send()
        conn.flush(TIMEOUT)
        assert conn.device.acked_samples == 1


def test_a_script_that_never_closes_still_delivers_what_it_sent(fake: FakeServer) -> None:
    """The thesis's scripts end without closing: at exit the device flushes what it has."""
    script = (
        "import twinlink_edge.compat as digitalTwinPlt\n"
        "dthub = digitalTwinPlt.Connect(device_id='fake-device', topic='demo')\n"
        "for i in range(250):\n"
        "    dthub.add_to_message(name='i', value=i)\n"
        "    dthub.send()\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 0 and not done.stderr, done.stderr
    values = [s["values"]["i"] for b in fake.batches() for s in b["samples"]]
    assert values == list(range(250))
