"""Commands over the live WebSocket (`{"op": "command"}` on GET /api/v1/live): a real server, a
device on the device WebSocket answering them, and the answers compared with the HTTP API's."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

import httpx
import orjson
import pytest
from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed

from tests.conftest import Server
from tests.integration._device import WAIT_S, FakeDevice, admin_client, make_twin
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import make_user, unique

pytestmark = pytest.mark.integration

RIG_INTERFACE = {
    "commands": [
        {"name": "pause", "parameters": []},
        {
            "name": "set_rate",
            "parameters": [{"name": "value", "type": "number", "min": 1, "max": 100}],
        },
    ]
}


@asynccontextmanager
async def live(server: Server, token: str) -> AsyncIterator[ClientConnection]:
    url = server.url.replace("http://", "ws://") + "/api/v1/live"
    async with connect(url, additional_headers={"Authorization": f"Bearer {token}"}) as ws:
        welcome = await recv(ws)
        assert welcome["type"] == "welcome" and welcome["limits"]["commands"] == 256
        yield ws


async def recv(ws: ClientConnection) -> dict[str, Any]:
    return orjson.loads(await asyncio.wait_for(ws.recv(), WAIT_S))  # type: ignore[no-any-return]


async def command(ws: ClientConnection, op_id: str, twin: str, name: str, **fields: Any) -> None:
    message = {"op": "command", "id": op_id, "twin": twin, "name": name, **fields}
    await ws.send(orjson.dumps(message).decode())


async def ask(ws: ClientConnection, twin: str, name: str, **fields: Any) -> dict[str, Any]:
    """Send one command op and return its answer (a `command` or an `error` message)."""
    await command(ws, "c1", twin, name, **fields)
    answer = await recv(ws)
    assert answer["id"] == "c1", answer
    return answer


def grant(server: Server, slug: str, username: str, role: str | None) -> None:
    with server.admin as admin:
        if role is None:
            r = admin.delete(f"/api/v1/twins/{slug}/roles/{username}")
        else:
            r = admin.put(f"/api/v1/twins/{slug}/roles/{username}", json={"role": role})
    assert r.status_code == 200, r.text


async def test_a_command_round_trip_answers_the_record_the_http_api_shows(server: Server) -> None:
    slug, tokens = make_twin(server, RIG_INTERFACE)
    async with (
        FakeDevice(server, tokens["rig"]),
        live(server, server.admin_token) as ws,
        admin_client(server) as client,
    ):
        answer = await ask(ws, slug, "set_rate", args={"value": 50}, timeout_s=10)
        assert answer["type"] == "command", answer
        cmd = answer["command"]
        assert (cmd["state"], cmd["device"], cmd["sent_by"]) == ("succeeded", "rig", "admin")
        assert cmd["result"] == {"name": "set_rate", "args": {"value": 50}}
        got = await client.get(f"/api/v1/twins/{slug}/commands/{cmd['id']}")
        assert got.json() == cmd


async def test_without_wait_the_answer_comes_at_once(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with (
        FakeDevice(server, tokens["rig"], answer=None),
        live(server, server.admin_token) as ws,
    ):
        answer = await ask(ws, slug, "calibrate", wait=False)
    assert answer["type"] == "command" and answer["command"]["state"] == "pending"


async def test_many_commands_in_flight_on_one_connection(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with FakeDevice(server, tokens["rig"]), live(server, server.admin_token) as ws:
        ids = [f"op-{i}" for i in range(100)]
        for op_id in ids:
            await command(ws, op_id, slug, "pause")
        answers = [await recv(ws) for _ in ids]
    assert sorted(a["id"] for a in answers) == sorted(ids)
    assert {a["command"]["state"] for a in answers} == {"succeeded"}
    assert len({a["command"]["id"] for a in answers}) == len(ids)


async def test_refusals_are_errors_naming_the_op(server: Server) -> None:
    slug, _ = make_twin(server, RIG_INTERFACE, devices=("a", "b"))
    name = unique("viewer")
    viewer = make_user(server, name)
    grant(server, slug, name, "viewer")
    async with live(server, viewer) as ws:
        refused = await ask(ws, slug, "pause")
        unknown = await ask(ws, "no-such-twin", "pause")
        malformed = await ask(ws, slug, "pause", args=[1])
    async with live(server, server.admin_token) as ws:
        several = await ask(ws, slug, "pause")
        wrong = await ask(ws, slug, "set_rate", device="a", args={"value": 500})
        offline = await ask(ws, slug, "pause", device="a")
    assert refused["type"] == "error" and refused["op"] == "command" and refused["status"] == 403
    assert refused["message"].startswith("a viewer cannot send commands")
    assert (unknown["status"], unknown["message"]) == (404, "no twin 'no-such-twin'")
    assert malformed["status"] == 422 and '"args" must be an object' in malformed["message"]
    assert several["status"] == 422 and "several devices (a, b)" in several["message"]
    assert wrong["status"] == 422 and "above the maximum 100" in wrong["message"]
    assert offline["type"] == "command" and offline["command"]["error"] == "device offline"


async def test_a_role_taken_away_counts_from_the_next_command(server: Server) -> None:
    slug, tokens = make_twin(server)
    name = unique("editor")
    editor = make_user(server, name)
    grant(server, slug, name, "editor")
    async with FakeDevice(server, tokens["rig"]), live(server, editor) as ws:
        assert (await ask(ws, slug, "pause"))["command"]["state"] == "succeeded"
        grant(server, slug, name, "viewer")
        assert (await ask(ws, slug, "pause"))["status"] == 403
        grant(server, slug, name, "editor")
        assert (await ask(ws, slug, "pause"))["command"]["state"] == "succeeded"


async def test_a_token_revoked_while_connected_closes_at_the_next_command(server: Server) -> None:
    slug, _ = make_twin(server)
    name = unique("editor")
    token = make_user(server, name)
    grant(server, slug, name, "editor")
    async with live(server, token) as ws:
        assert (await ask(ws, slug, "pause"))["type"] == "command"  # the token is cached now
        async with httpx.AsyncClient(base_url=server.url) as client:
            r = await client.post(
                "/api/v1/auth/logout", headers={"Authorization": f"Bearer {token}"}
            )
            assert r.status_code == 200
        await command(ws, "c2", slug, "pause")
        try:
            while True:
                await asyncio.wait_for(ws.recv(), WAIT_S)
        except ConnectionClosed as closed:
            assert closed.rcvd is not None and closed.rcvd.code == 4401
            assert closed.rcvd.reason == "the token has been revoked"
