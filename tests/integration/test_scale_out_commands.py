"""Commands across two `twinlink up` nodes sharing one PostgreSQL database and one Kafka broker
(docs/scale-out.md): a command posted on node A to a device connected to node B reaches it, and
A answers with what the device did, as for a device of its own; a queued command is delivered
by the node the device connects to, once."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import httpx
import pytest

from tests.conftest import Server, stop_server
from tests.integration._device import WAIT_S, FakeDevice, admin_client, make_twin
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import cluster
from tests.integration._util import unhandled_errors

pytestmark = pytest.mark.integration

DEADLINE_S = 20.0  # for a state to reach the other node: the bus takes milliseconds


@dataclass
class Nodes:
    a: Server
    b: Server


@pytest.fixture(scope="module")
def nodes(
    postgres_cluster: PostgresCluster,
    kafka: KafkaBroker,
    tmp_path_factory: pytest.TempPathFactory,
) -> Iterator[Nodes]:
    with cluster(postgres_cluster, kafka) as shared:
        a = shared.start(tmp_path_factory.mktemp("node-a"))
        try:
            b = shared.start(tmp_path_factory.mktemp("node-b"), token=a.admin_token)
            try:
                yield Nodes(a, b)
            finally:
                stop_server(b)
        finally:
            stop_server(a)


@pytest.fixture(autouse=True)
def no_server_errors(nodes: Nodes) -> Iterator[None]:
    before = [unhandled_errors(nodes.a), unhandled_errors(nodes.b)]
    yield
    assert [unhandled_errors(nodes.a), unhandled_errors(nodes.b)] == before


async def send(
    client: httpx.AsyncClient, slug: str, name: str, **body: Any
) -> tuple[int, dict[str, Any]]:
    r = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": name, **body})
    assert r.status_code in (200, 202), r.text
    return r.status_code, r.json()


async def state_of(client: httpx.AsyncClient, slug: str, command_id: str) -> dict[str, Any]:
    r = await client.get(f"/api/v1/twins/{slug}/commands/{command_id}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


async def until_state(
    client: httpx.AsyncClient, slug: str, command_id: str, state: str
) -> dict[str, Any]:
    """The command once the node `client` asks shows it in `state` (AssertionError after
    DEADLINE_S): polls the real state, waits for nothing else."""
    deadline = asyncio.get_running_loop().time() + DEADLINE_S
    while True:
        found = await state_of(client, slug, command_id)
        if found["state"] == state:
            return found
        if asyncio.get_running_loop().time() > deadline:
            raise AssertionError(f"command {command_id} is {found['state']}, not {state}")
        await asyncio.sleep(0.05)  # polling the real state, not waiting for it to happen


async def commands_seen(device: FakeDevice) -> list[str]:
    """The ids of the `command` messages the device got until the server handled a `ping`
    sent now (it reads a device's messages in order; its `pong` comes after them all)."""
    await device.send({"type": "ping"})
    seen = []
    while (message := await asyncio.wait_for(device._inbox.get(), WAIT_S))["type"] != "pong":
        if message["type"] == "command":
            seen.append(message["id"])
    return seen


# -- a device on node B, a command posted on node A -----------------------------------------


async def test_a_command_posted_on_a_reaches_the_device_on_b_and_a_answers_its_result(
    nodes: Nodes,
) -> None:
    slug, tokens = make_twin(nodes.a)
    async with FakeDevice(nodes.b, tokens["rig"]) as device, admin_client(nodes.a) as a:
        status, cmd = await send(a, slug, "set_rate", args={"value": 5}, timeout_s=20)
        assert status == 200, cmd
        assert (cmd["state"], cmd["device"], cmd["sent_by"]) == ("succeeded", "rig", "admin")
        assert cmd["result"] == {"name": "set_rate", "args": {"value": 5}}
        assert cmd["delivered"] and cmd["finished"]
        assert await commands_seen(device) == [cmd["id"]]  # once, though two nodes read the bus
    async with admin_client(nodes.b) as b:  # the shared command log says the same
        assert (await until_state(b, slug, cmd["id"], "succeeded"))["result"] == cmd["result"]


async def test_a_failed_result_on_b_is_the_state_a_answers(nodes: Nodes) -> None:
    slug, tokens = make_twin(nodes.a)

    def refuse(command: dict[str, Any]) -> dict[str, Any]:
        return {"status": "failed", "error": f"cannot {command['name']} now"}

    async with FakeDevice(nodes.b, tokens["rig"], refuse), admin_client(nodes.a) as a:
        status, cmd = await send(a, slug, "open_valve", timeout_s=20)
    assert status == 200
    assert (cmd["state"], cmd["error"]) == ("failed", "cannot open_valve now")


async def test_without_wait_a_follows_delivered_then_the_result(nodes: Nodes) -> None:
    slug, tokens = make_twin(nodes.a)
    async with (
        FakeDevice(nodes.b, tokens["rig"], answer=None) as device,
        admin_client(nodes.a) as a,
    ):
        status, cmd = await send(a, slug, "calibrate", wait=False, timeout_s=60)
        # A answers once B took the command: the device may have said `delivered` by then.
        assert status == 202 and cmd["state"] in ("pending", "delivered")
        assert (await device.next("command"))["id"] == cmd["id"]
        delivered = await until_state(a, slug, cmd["id"], "delivered")
        assert delivered["delivered"] and delivered["finished"] is None
        await device.send({"type": "result", "id": cmd["id"], "status": "succeeded",
                           "result": 7})  # fmt: skip
        done = await until_state(a, slug, cmd["id"], "succeeded")
    assert done["result"] == 7


async def test_no_answer_from_the_device_on_b_expires_on_a(nodes: Nodes) -> None:
    slug, tokens = make_twin(nodes.a)
    async with FakeDevice(nodes.b, tokens["rig"], answer=None), admin_client(nodes.a) as a:
        status, cmd = await send(a, slug, "slow", timeout_s=5)
    assert status == 200
    assert cmd["state"] == "expired" and cmd["delivered"] and cmd["result"] is None


async def test_a_device_on_no_node_is_offline(nodes: Nodes) -> None:
    slug, _ = make_twin(nodes.a)
    async with admin_client(nodes.a) as a:
        status, cmd = await send(a, slug, "pause")
    assert status == 200
    assert (cmd["state"], cmd["error"]) == ("failed", "device offline")


async def test_the_device_on_b_is_still_a_devices_own_on_a(nodes: Nodes) -> None:
    """The device on B answering a command B sent itself: unchanged by the relay."""
    slug, tokens = make_twin(nodes.a)
    async with FakeDevice(nodes.b, tokens["rig"]) as device, admin_client(nodes.b) as b:
        status, cmd = await send(b, slug, "pause", timeout_s=20)
        assert status == 200 and cmd["state"] == "succeeded"
        assert await commands_seen(device) == [cmd["id"]]


# -- queued commands ---------------------------------------------------------------------------


async def test_a_queued_command_from_a_is_delivered_once_when_the_device_connects_to_b(
    nodes: Nodes,
) -> None:
    slug, tokens = make_twin(nodes.a)
    async with admin_client(nodes.a) as a:
        status, cmd = await send(a, slug, "pause", queue=True, wait=False, timeout_s=60)
        assert status == 202 and (cmd["state"], cmd["queued"]) == ("pending", True)
        async with FakeDevice(nodes.b, tokens["rig"]) as device:
            assert (await device.next("command"))["id"] == cmd["id"]
            done = await until_state(a, slug, cmd["id"], "succeeded")
            assert await commands_seen(device) == []  # not a second time
    assert done["result"] == {"name": "pause", "args": {}}


async def test_a_sender_waiting_on_a_gets_the_result_of_a_queued_command_run_on_b(
    nodes: Nodes,
) -> None:
    slug, tokens = make_twin(nodes.a)
    async with admin_client(nodes.a) as a:
        sending = asyncio.create_task(send(a, slug, "pause", queue=True, timeout_s=30))
        # The command is queued on A (pending) before the device connects to B.
        async with admin_client(nodes.a) as reader:
            deadline = asyncio.get_running_loop().time() + DEADLINE_S
            while not (await reader.get(f"/api/v1/twins/{slug}/commands")).json()["commands"]:
                assert asyncio.get_running_loop().time() < deadline, "the command was not made"
                await asyncio.sleep(0.05)
        async with FakeDevice(nodes.b, tokens["rig"]) as device:
            await device.next("command")
            status, cmd = await sending
    assert status == 200 and cmd["state"] == "succeeded"


async def test_a_device_polling_b_over_http_gets_a_command_from_a_and_a_gets_its_result(
    nodes: Nodes,
) -> None:
    slug, tokens = make_twin(nodes.a)
    headers = {"Authorization": f"Bearer {tokens['rig']}"}
    async with (
        admin_client(nodes.a) as a,
        httpx.AsyncClient(base_url=nodes.b.url, headers=headers, timeout=30) as device,
    ):
        # Queued, so it waits on A for the poll on B whichever comes first.
        sending = asyncio.create_task(send(a, slug, "pause", queue=True, timeout_s=30))
        polled = await device.get("/api/v1/device/commands", params={"wait": 20})
        assert polled.status_code == 200, polled.text
        [command] = polled.json()["commands"]
        assert command["name"] == "pause"
        r = await device.post(
            f"/api/v1/device/commands/{command['id']}/result",
            json={"status": "succeeded", "result": "paused"},
        )
        assert r.status_code == 200 and r.json()["state"] == "succeeded", r.text
        status, cmd = await sending
        assert (status, cmd["id"], cmd["state"], cmd["result"]) == (
            200, command["id"], "succeeded", "paused",
        )  # fmt: skip
        assert cmd["delivered"] is not None
        again = await device.get("/api/v1/device/commands")  # delivered once
        assert again.json()["commands"] == []


# -- desired and reported properties -----------------------------------------------------------


def properties_url(slug: str, tail: str = "") -> str:
    return f"/api/v1/twins/{slug}/devices/rig/properties{tail}"


async def test_desired_values_set_on_a_reach_the_device_on_b(nodes: Nodes) -> None:
    slug, tokens = make_twin(nodes.a)
    async with admin_client(nodes.b) as b:  # B has the device's properties cached now
        assert (await b.get(properties_url(slug))).json()["version"] == 0
    async with FakeDevice(nodes.b, tokens["rig"]) as device, admin_client(nodes.a) as a:
        r = await a.patch(properties_url(slug, "/desired"), json={"rate": 50, "mode": "eco"})
        assert r.status_code == 200, r.text
        sent = await device.next("desired")  # through Kafka, from node B
        assert sent == {"type": "desired", "properties": {"rate": 50, "mode": "eco"},
                        "version": 1}  # fmt: skip
        # B's answer to the device's report knows the new desired values (not its old cache).
        await device.send({"type": "reported", "id": "r1", "properties": {"rate": 50}})
        ack = await device.next("reported_ack")
        assert ack == {"type": "reported_ack", "version": 1, "desired": {"mode": "eco"},
                       "id": "r1"}  # fmt: skip

        async def delta_on_a() -> dict[str, Any]:
            return (await a.get(properties_url(slug))).json()["delta"]  # type: ignore[no-any-return]

        # A, which cached the device's properties when it set them, follows the report on B.
        deadline = asyncio.get_running_loop().time() + DEADLINE_S
        while (delta := await delta_on_a()) != {"mode": "eco"}:
            assert asyncio.get_running_loop().time() < deadline, delta
            await asyncio.sleep(0.05)  # polling the real state, not waiting for it to happen
