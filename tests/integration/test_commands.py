"""Commands: a real server, a device on the WebSocket (or HTTP) answering them, the log."""

from __future__ import annotations

import asyncio
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from websockets.asyncio.client import connect
from websockets.exceptions import ConnectionClosed

from tests.conftest import Server, start_server, stop_server
from tests.integration._device import FakeDevice, admin_client, make_twin
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration

RIG_INTERFACE = {
    "commands": [
        {"name": "pause", "parameters": []},
        {
            "name": "set_sample_rate",
            "parameters": [
                {"name": "value", "type": "number", "min": 1, "max": 100, "required": True},
                {"name": "ramp", "type": "bool", "default": False},
                {"name": "label", "type": "string"},
                {"name": "steps", "type": "integer"},
            ],
        },
    ]
}


async def send(
    client: httpx.AsyncClient, slug: str, name: str, **body: Any
) -> tuple[int, dict[str, Any]]:
    r = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": name, **body})
    assert r.status_code in (200, 202), r.text
    return r.status_code, r.json()


# -- round trips ---------------------------------------------------------------------------


async def test_round_trip_succeeds_and_is_logged(server: Server) -> None:
    slug, tokens = make_twin(server, RIG_INTERFACE)
    async with FakeDevice(server, tokens["rig"]), admin_client(server) as client:
        status, cmd = await send(client, slug, "set_sample_rate", args={"value": 50})
        assert status == 200
        assert cmd["state"] == "succeeded" and cmd["device"] == "rig"
        # the default of `ramp` was filled in; the device saw the same arguments
        assert cmd["args"] == {"value": 50, "ramp": False}
        assert cmd["result"] == {"name": "set_sample_rate", "args": {"value": 50, "ramp": False}}
        assert cmd["delivered"] and cmd["finished"] and cmd["sent_by"] == "admin"
        one = await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")
        assert one.json() == cmd
        log = (await client.get(f"/api/v1/twins/{slug}/commands")).json()["commands"]
        assert [c["id"] for c in log] == [cmd["id"]]


async def test_a_failed_result_is_the_command_s_state(server: Server) -> None:
    slug, tokens = make_twin(server)

    def refuse(command: dict[str, Any]) -> dict[str, Any]:
        return {"status": "failed", "error": f"cannot {command['name']} now"}

    async with FakeDevice(server, tokens["rig"], refuse), admin_client(server) as client:
        status, cmd = await send(client, slug, "open_valve", args={"valve": {"id": 3}})
        assert status == 200
        assert (cmd["state"], cmd["error"], cmd["result"]) == (
            "failed",
            "cannot open_valve now",
            None,
        )
        failed = await client.get(f"/api/v1/twins/{slug}/commands", params={"state": "failed"})
        assert [c["id"] for c in failed.json()["commands"]] == [cmd["id"]]
        succeeded = await client.get(
            f"/api/v1/twins/{slug}/commands", params={"state": "succeeded"}
        )
        assert succeeded.json()["commands"] == []


async def test_no_result_in_time_expires_and_a_late_result_is_kept(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with (
        FakeDevice(server, tokens["rig"], answer=None) as device,
        admin_client(server) as client,
    ):
        status, cmd = await send(client, slug, "slow", timeout_s=1.0)
        assert status == 200
        assert cmd["state"] == "expired" and cmd["delivered"] and cmd["result"] is None
        await device.send({"type": "result", "id": cmd["id"], "status": "succeeded",
                           "result": 42})  # fmt: skip
        await device.settle()
        late = (await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")).json()
    assert (late["state"], late["late_status"], late["result"]) == ("expired", "succeeded", 42)


async def test_without_wait_the_answer_is_202_and_the_id_can_be_polled(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with (
        FakeDevice(server, tokens["rig"], answer=None) as device,
        admin_client(server) as client,
    ):
        status, cmd = await send(client, slug, "calibrate", wait=False)
        assert status == 202 and cmd["state"] == "pending"
        sent = await device.next("command")
        assert sent["id"] == cmd["id"] and sent["args"] == {} and sent["expires"] > 0
        await device.settle()  # `delivered` has been handled
        got = (await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")).json()
        assert got["state"] == "delivered"
        await device.send({"type": "result", "id": cmd["id"], "status": "succeeded"})
        await device.settle()
        got = (await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")).json()
        assert got["state"] == "succeeded"


async def test_bad_results_get_an_error_message(server: Server) -> None:
    _, tokens = make_twin(server)
    async with FakeDevice(server, tokens["rig"], answer=None) as device:
        await device.send({"type": "result", "id": "nope", "status": "succeeded"})
        assert "no command 'nope'" in (await device.next("error"))["message"]
        await device.send({"type": "result", "id": "nope", "status": "done"})
        assert "status" in (await device.next("error"))["message"]


# -- offline devices -------------------------------------------------------------------------


async def test_offline_without_queue_fails_at_once(server: Server) -> None:
    slug, _ = make_twin(server)
    async with admin_client(server) as client:
        status, cmd = await send(client, slug, "pause")
    assert status == 200
    assert (cmd["state"], cmd["error"]) == ("failed", "device offline")


async def test_queued_command_is_delivered_when_the_device_connects(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with admin_client(server) as client:
        status, cmd = await send(client, slug, "pause", queue=True, wait=False)
        assert status == 202 and cmd["state"] == "pending" and cmd["queued"] is True
        async with FakeDevice(server, tokens["rig"]) as device:
            assert (await device.next("command"))["id"] == cmd["id"]
            await device.settle()
            got = (await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")).json()
    assert got["state"] == "succeeded"


async def test_a_waiting_sender_gets_the_result_of_a_queued_command(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with admin_client(server) as client:
        sending = asyncio.create_task(send(client, slug, "pause", queue=True, timeout_s=20))
        # The sender is waiting (or about to): a device that connects now gets the command.
        async with FakeDevice(server, tokens["rig"]) as device:
            await device.next("command")
            status, cmd = await sending
    assert status == 200 and cmd["state"] == "succeeded"


@pytest.fixture
def own_server(tmp_path: Path) -> Iterator[list[Server]]:
    started: list[Server] = []
    yield started
    for s in started:
        stop_server(s)


async def test_a_queued_command_survives_a_server_restart(
    tmp_path: Path, own_server: list[Server]
) -> None:
    first = start_server(tmp_path)
    own_server.append(first)
    slug, tokens = make_twin(first)
    async with admin_client(first) as client:
        _, kept = await send(client, slug, "pause", queue=True, wait=False, timeout_s=600)
        _, gone = await send(client, slug, "start", queue=True, wait=False, timeout_s=0.2)
    stop_server(first)
    second = start_server(tmp_path)
    own_server.append(second)
    async with FakeDevice(second, tokens["rig"]) as device, admin_client(second) as client:
        assert (await device.next("command"))["id"] == kept["id"]
        await device.settle()
        got = (await client.get(f"/api/v1/twins/{slug}/commands/{kept['id']}")).json()
        assert got["state"] == "succeeded"
        expired = (await client.get(f"/api/v1/twins/{slug}/commands/{gone['id']}")).json()
        assert expired["state"] == "expired"


# -- HTTP devices ----------------------------------------------------------------------------


async def test_a_device_without_a_websocket_polls_and_posts_results(server: Server) -> None:
    slug, tokens = make_twin(server)
    headers = {"Authorization": f"Bearer {tokens['rig']}"}
    async with (
        admin_client(server) as client,
        httpx.AsyncClient(base_url=server.url, headers=headers, timeout=30) as device,
    ):
        # queued (or handed to the poll if it is already waiting): delivered either way
        sending = asyncio.create_task(send(client, slug, "pause", queue=True, timeout_s=20))
        polled = await device.get("/api/v1/device/commands", params={"wait": 10})
        assert polled.status_code == 200, polled.text
        [command] = polled.json()["commands"]
        assert command["name"] == "pause"
        r = await device.post(
            f"/api/v1/device/commands/{command['id']}/result",
            json={"status": "succeeded", "result": "paused"},
        )
        assert r.status_code == 200 and r.json()["state"] == "succeeded", r.text
        status, cmd = await sending
        assert (status, cmd["result"]) == (200, "paused")
        empty = await device.get("/api/v1/device/commands")
        assert empty.json()["commands"] == []
        assert_problem(await device.post("/api/v1/device/commands/nope/result",
                                         json={"status": "failed"}), 404)  # fmt: skip


# -- rights, devices and arguments -----------------------------------------------------------


def test_viewers_cannot_send_and_strangers_do_not_see_the_twin(server: Server) -> None:
    slug, _ = make_twin(server)
    viewer, stranger = unique("viewer"), unique("stranger")
    viewer_token, stranger_token = make_user(server, viewer), make_user(server, stranger)
    with server.admin as admin:
        hidden = unique("hidden")
        apply(admin, twin_doc(f"urn:{hidden}", slug=hidden, privacy="private"))
        for twin in (slug, hidden):
            r = admin.put(f"/api/v1/twins/{twin}/roles/{viewer}", json={"role": "viewer"})
            assert r.status_code == 200, r.text
    with server.client(viewer_token) as c:
        problem = assert_problem(c.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"}), 403)
        assert "a viewer cannot send commands" in problem["detail"]
        assert c.get(f"/api/v1/twins/{slug}/commands").status_code == 200
    with server.client(stranger_token) as c:
        assert_problem(c.post(f"/api/v1/twins/{hidden}/commands", json={"name": "x"}), 404)
        assert_problem(c.get(f"/api/v1/twins/{hidden}/commands"), 404)
        # the twin's document is public, its command log is not
        assert_problem(c.get(f"/api/v1/twins/{slug}/commands"), 403)


async def test_tokens_open_only_their_own_side(server: Server) -> None:
    slug, tokens = make_twin(server)
    with server.client(tokens["rig"]) as device:
        assert_problem(device.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"}), 401)
        assert_problem(device.get(f"/api/v1/twins/{slug}/commands"), 401)
    with server.admin as person:
        assert_problem(person.get("/api/v1/device/commands"), 401)
        assert_problem(person.post("/api/v1/device/commands/x/result",
                                   json={"status": "failed"}), 401)  # fmt: skip
    url = server.url.replace("http://", "ws://") + "/api/v1/device/ws"
    auth = {"Authorization": f"Bearer {server.admin_token}"}
    async with connect(url, additional_headers=auth) as ws:
        with pytest.raises(ConnectionClosed) as closed:
            await asyncio.wait_for(ws.recv(), 15)
    assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401


@pytest.mark.parametrize(
    ("name", "args", "reason"),
    [
        (
            "reboot",
            {},
            "the twin has no command 'reboot'; its commands are: pause, set_sample_rate",
        ),
        ("set_sample_rate", {}, "the argument 'value' is required"),
        ("set_sample_rate", {"value": 500}, "500 is above the maximum 100"),
        ("set_sample_rate", {"value": "fast"}, "'value': \"fast\" is not a number"),
        ("set_sample_rate", {"value": 5, "steps": 1.5}, "'steps': 1.5 is not an integer"),
        ("set_sample_rate", {"value": 5, "ramp": 1}, "'ramp': 1 is not a bool"),
        ("set_sample_rate", {"value": 5, "speed": 1}, "unknown argument 'speed'"),
        ("pause", {"now": True}, "unknown argument 'now'; it takes no arguments"),
        ("bad name", {}, "must match"),
    ],
)
def test_wrong_arguments_are_refused_with_the_reason(
    server: Server, name: str, args: dict[str, Any], reason: str
) -> None:
    slug, _ = make_twin(server, RIG_INTERFACE)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": name, "args": args})
    assert reason in assert_problem(r, 422)["detail"]


def test_the_device_must_be_named_when_a_twin_has_several(server: Server) -> None:
    slug, _ = make_twin(server, devices=("left", "right"))
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
        detail = assert_problem(r, 422)["detail"]
        assert "several devices (left, right)" in detail
        named = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x", "device": "right"})
        assert named.json()["device"] == "right" and named.json()["error"] == "device offline"
        missing = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x", "device": "up"})
        assert_problem(missing, 404)
        bad = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x", "timeout_s": 0})
        assert_problem(bad, 422)
        listed = admin.get(f"/api/v1/twins/{slug}/commands", params={"device": "right"})
        assert [c["device"] for c in listed.json()["commands"]] == ["right"]
        assert_problem(admin.get(f"/api/v1/twins/{slug}/commands", params={"state": "x"}), 422)
        assert_problem(admin.get(f"/api/v1/twins/{slug}/commands/nope"), 404)


async def test_the_device_view_says_whether_it_is_connected(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with admin_client(server) as client:
        assert (await client.get(f"/api/v1/twins/{slug}/devices/rig")).json()["connected"] is False
        async with FakeDevice(server, tokens["rig"]):
            listed = (await client.get(f"/api/v1/twins/{slug}/devices")).json()["devices"]
            assert listed[0]["connected"] is True


# -- the CLI ---------------------------------------------------------------------------------


async def test_cli_sends_and_lists_commands(server: Server, tmp_path: Path) -> None:
    slug, tokens = make_twin(server, RIG_INTERFACE)
    env = {
        **os.environ,
        "TWINLINK_URL": server.url,
        "TWINLINK_TOKEN": server.admin_token,
        "XDG_CONFIG_HOME": str(tmp_path),
    }

    async def cli(*args: str) -> tuple[int, str, str]:
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "twinlink", *args, env=env, stdin=asyncio.subprocess.DEVNULL,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        out, err = await asyncio.wait_for(proc.communicate(), 60)
        assert proc.returncode is not None
        return proc.returncode, out.decode(), err.decode()

    async with FakeDevice(server, tokens["rig"]):
        code, out, err = await cli("send", slug, "set_sample_rate", "value=50", "label=fast")
        assert code == 0, err
        assert "succeeded" in out and '"label": "fast"' in out and '"value": 50' in out
        code, out, err = await cli("send", slug, "set_sample_rate", "value=500")
        assert code == 1 and "above the maximum 100" in err and "Traceback" not in err
    code, out, err = await cli("send", slug, "pause", "--no-wait", "--queue")
    assert code == 0 and "pending" in out, err
    code, out, err = await cli("commands", "ls", slug)
    assert code == 0, err
    rows = [line.split()[2:5] for line in out.splitlines()]  # device, name, state
    assert rows == [["rig", "pause", "pending"], ["rig", "set_sample_rate", "succeeded"]]
