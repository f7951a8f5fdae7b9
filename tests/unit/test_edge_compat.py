"""twinlink_edge.compat: the NTNU thesis's device code runs with only its import changed.
Runs against FakeServer (tests/unit/test_edge_device.py), an in-process fake server."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest

import twinlink_edge.compat
import twinlink_edge.compat as digitalTwinPlt
from tests.conftest import free_port
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


def answers(fake: FakeServer) -> list[tuple[str, object]]:
    """The device's answers to commands, in order: ("delivered", id) or (status, id)."""
    return [
        ("delivered" if m["type"] == "delivered" else str(m["status"]), m["id"])
        for m in fake.received
        if m["type"] in ("delivered", "result")
    ]


def test_the_thesis_listing_runs(fake: FakeServer) -> None:
    """Listing 5.1, with a `pause` queued for the device before the script connects."""
    fake.queued = [command("c1", "pause")]
    dtMessaging = Connect(device_id="fake-device", topic="0000")
    try:
        dtMessaging.add_to_message(name="Temperature", value=20)
        dtMessaging.add_to_message(name="Input_F_in", value=8)
        dtMessaging.send()
        dtMessaging.add_to_message(name="Input_F_in", value=9)  # updates; Temperature stays
        dtMessaging.send()
        dtMessaging.flush(TIMEOUT)
        assert answers(fake) == []  # arrived, but not handed over yet
        paused = []
        instruction = dtMessaging.receive()  # once, as in the listing: no wait, no retry
        for _topic, partition_msg in instruction.items():
            for m in partition_msg:
                if m.value == b"pause":
                    paused.append(m)
        fake.wait(lambda f: len(answers(f)) == 2)
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
    assert paused[0].timestamp <= time.time_ns() // 1_000_000
    assert answers(fake) == [("delivered", "c1"), ("succeeded", "c1")]


def arrived(conn: Connect) -> None:
    """A round trip to the fake: what it sent before has reached the device."""
    conn.device._call(conn.device.aio._round_trip(TIMEOUT))


def test_commands_never_read_are_answered_failed_at_close(fake: FakeServer) -> None:
    fake.queued = [command("q", "pause")]
    conn = Connect(topic="t")
    try:
        fake.push(command("read", "stop", {"after": 2}))
        arrived(conn)
        assert [m.name for m in conn.receive()["t"]] == ["pause", "stop"]
        fake.push(command("unread", "start"))
        arrived(conn)
    finally:
        conn.close()
    assert answers(fake) == [
        ("delivered", "q"),
        ("succeeded", "q"),
        ("delivered", "read"),
        ("succeeded", "read"),
        ("failed", "unread"),  # never handed over: not delivered either
    ]
    assert fake.of_type("result")[-1]["error"] == "not read by the device"


def test_a_command_sent_again_while_it_waits_is_handed_over_once(fake: FakeServer) -> None:
    """The server sends a queued command again on each connection until it is delivered."""
    fake.queued = [command("q", "pause")]
    conn = Connect(topic="t")
    try:
        fake.drop()
        fake.wait(lambda f: f.connections == 2)
        assert conn.device.wait_connected(TIMEOUT)
        arrived(conn)  # the second copy has come
        assert [m.name for m in conn.receive()["t"]] == ["pause"]
        fake.wait(lambda f: len(answers(f)) == 2)
    finally:
        conn.close()
    assert answers(fake) == [("delivered", "q"), ("succeeded", "q")]


def test_connect_returns_connected_or_says_why_not(fake: FakeServer) -> None:
    with Connect(topic="t", backoff_initial=0.01) as conn:
        assert conn.device.connected  # at once: no wait_connected() needed
    refused = r"not connected within 0.5 s: the server refused the device token \(401\)"
    with pytest.raises(ConnectionError, match=refused):
        Connect(token="tld_wrong", connect_timeout=0.5, backoff_initial=0.01)
    nobody = f"http://127.0.0.1:{free_port()}"  # nothing listens there
    with pytest.raises(ConnectionError, match=r"within 0.5 s: cannot connect to ws://127.0.0.1"):
        Connect(url=nobody, connect_timeout=0.5, backoff_initial=0.01)


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
    inbox = conn.device.aio._dispatcher.inbox
    assert inbox is not None
    waits: list[float] = []
    waiting = threading.Event()
    wait = inbox.wait

    async def note_the_wait(timeout: float) -> None:
        waits.append(timeout)
        if timeout:
            waiting.set()
        await wait(timeout)

    monkeypatch.setattr(inbox, "wait", note_the_wait)
    try:
        conn.add_to_message("x", 1)
        assert conn.receive() == {}  # the first call: at once
        conn.send()
        assert conn.receive() == {}  # a send since the last call: at once
        assert waits == []  # neither waited (nor needed the device's loop)
        # Nothing sent, the last call empty: this one waits, and takes the command that comes.

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
        assert conn.receive() == {}  # the last call returned data: at once
        assert conn.receive(timeout_ms=0) == {}
        assert conn.receive(timeout_ms=1) == {}
        assert waits == [TIMEOUT, 0.001]
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
