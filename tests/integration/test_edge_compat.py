"""The NTNU thesis's device code through `twinlink_edge.compat`, against the real server: a
`pause` queued before the script connects reaches listing 5.1's single `receive()`, and
counts as delivered (then succeeded) only once handed over; a script that exits without
reading leaves it failed, "not read by the device"."""

from __future__ import annotations

import os
import subprocess
import sys
from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import device_twin
from tests.integration._util import poll_until
from tests.integration.test_edge_sdk import TIMEOUT, history
from twinlink_edge.compat import Connect

pytestmark = pytest.mark.integration

LISTING_5_1 = """
from twinlink_edge.compat import Connect  # was: from digitalTwinPlt import Connect

dtMessaging = Connect(device_id='dev0', topic='0000')

dtMessaging.add_to_message(name='Temperature', value=20)
dtMessaging.add_to_message(name='Humidity', value=78)
dtMessaging.add_to_message(name='Input_F_in', value=8)
dtMessaging.send()
"""


def queue_command(admin: httpx.Client, slug: str, name: str) -> str:
    """Send `name` to the twin's device with `queue`, not waiting; its id."""
    body = {"name": name, "queue": True, "wait": False, "timeout_s": 2 * TIMEOUT}
    r = admin.post(f"/api/v1/twins/{slug}/commands", json=body)
    assert r.status_code == 202 and r.json()["state"] == "pending", r.text
    return str(r.json()["id"])


def command_record(admin: httpx.Client, slug: str, cid: str) -> dict[str, Any]:
    r = admin.get(f"/api/v1/twins/{slug}/commands/{cid}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_listing_5_1_receives_a_pause_queued_before_it_connected(
    server: Server, monkeypatch: pytest.MonkeyPatch
) -> None:
    slug, (token,) = device_twin(server)
    monkeypatch.setenv("TWINLINK_URL", server.url)
    monkeypatch.setenv("TWINLINK_DEVICE_TOKEN", token)
    paused = []

    def pause() -> None:
        paused.append(True)

    with server.admin as admin:
        cid = queue_command(admin, slug, "pause")
        # Listing 5.1, line for line.
        dtMessaging = Connect(device_id="dev0", topic="0000")
        try:
            dtMessaging.add_to_message(name="Temperature", value=20)
            dtMessaging.add_to_message(name="Humidity", value=78)
            dtMessaging.add_to_message(name="Input_F_in", value=8)
            dtMessaging.send()
            before = command_record(admin, slug, cid)  # the device has it, unread
            instruction = dtMessaging.receive()
            for _topic, partition_msg in instruction.items():
                for m in partition_msg:
                    if m.value == b"pause":
                        pause()
            dtMessaging.flush(TIMEOUT)
            after = poll_until(
                lambda: (r := command_record(admin, slug, cid))["state"] == "succeeded" and r,
                "the command to succeed",
            )
        finally:
            dtMessaging.close()
    assert (before["state"], before["delivered"]) == ("pending", None)
    assert paused == [True] and list(instruction) == ["0000"]
    assert after["delivered"] is not None and after["error"] is None
    [row] = history(server, slug)
    assert row["values"] == {"Temperature": 20, "Humidity": 78, "Input_F_in": 8}


def test_a_script_that_exits_without_reading_leaves_the_command_failed(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with server.admin as admin:
        cid = queue_command(admin, slug, "pause")
        env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_DEVICE_TOKEN": token}
        done = subprocess.run(
            [sys.executable, "-c", LISTING_5_1],  # no receive(), no close(): it just ends
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        assert done.returncode == 0, done.stderr
        record = command_record(admin, slug, cid)
    assert (record["state"], record["error"]) == ("failed", "not read by the device")
    # No `delivered` came before the result (the server counts a result as delivery too).
    assert record["delivered"] == record["finished"]
    assert "command 'pause'" in done.stderr and "not read by the device" in done.stderr
    [row] = history(server, slug)
    assert row["values"] == {"Temperature": 20, "Humidity": 78, "Input_F_in": 8}
