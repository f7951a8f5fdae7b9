"""A WoT consumer follows the forms of a twin's Thing Description (docs/formats.md, "WoT
Thing Description") on a real server: each form's href, method and URI variables reach the
endpoint it names, and the device links take the device's telemetry."""

from __future__ import annotations

import asyncio
import json
from typing import Any

import pytest
from websockets.asyncio.client import connect

from tests.conftest import EXAMPLES, Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from twinlink.formats.wot import validate_wot

pytestmark = pytest.mark.integration

ANGLE = "Cantilever_Angle_radians"


@pytest.fixture(scope="module")
def rig(server: Server) -> tuple[dict[str, Any], str]:
    """Tingen with its device, and the TD a signed-in reader gets: (td, device token)."""
    with server.admin as admin:
        r = admin.post(
            "/api/v1/apply",
            content=(EXAMPLES / "tingen" / "tingen.yaml").read_bytes(),
            headers={"Content-Type": "application/yaml"},
        )
        assert r.status_code == 200, r.text
        slug = r.json()["results"][0]["slug"]
        r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "tingenSAP"})
        assert r.status_code in (200, 201), r.text
        token = r.json()["token"]
        td = admin.get(f"/twins/{slug}", params={"format": "wot-td"}).json()
    assert validate_wot(td) == []
    return td, token


def _form(affordance: dict[str, Any], op: str) -> dict[str, Any]:
    return next(
        f for f in affordance["forms"] if op in ([f["op"]] if isinstance(f["op"], str) else f["op"])
    )


def _expand(href: str, affordance: dict[str, Any]) -> str:
    """RFC 6570 level 1, as a consumer does it: each variable's value, or its default."""
    for name, schema in affordance.get("uriVariables", {}).items():
        href = href.replace("{" + name + "}", str(schema["default"]))
    return href


def test_device_link_takes_samples_and_readproperty_reads_them(
    server: Server, rig: tuple[dict[str, Any], str]
) -> None:
    td, device_token = rig
    samples = next(
        link["href"] for link in td["links"]
        if link["rel"] == "twinlink:deviceIngest" and link["href"].endswith("/device/samples")
    )  # fmt: skip
    with server.client(device_token) as device:
        r = device.post(samples, json={"seq": 1, "samples": [{"values": {ANGLE: 0.25}}]})
    assert r.status_code == 200 and r.json()["accepted"] == 1, r.text
    read = _form(td["properties"][ANGLE], "readproperty")
    with server.admin as admin:
        values = admin.get(read["href"]).json()["values"]
    assert values[ANGLE]["value"] == 0.25


def test_property_forms_read_and_write_the_devices_properties(
    server: Server, rig: tuple[dict[str, Any], str]
) -> None:
    td, _ = rig
    rate = td["properties"]["sample_rate"]
    read, write = _form(rate, "readproperty"), _form(rate, "writeproperty")
    with server.admin as admin:
        r = admin.request(
            write["htv:methodName"], _expand(write["href"], rate), json={"sample_rate": 50}
        )
        assert r.status_code == 200, r.text
        got = admin.get(_expand(read["href"], rate)).json()
    assert got["device"] == "tingenSAP" and got["desired"]["sample_rate"]["value"] == 50
    # A property that is not writable has no form that writes it.
    assert not [f for f in td["properties"]["paused"]["forms"] if f["op"] == "writeproperty"]


def test_invokeaction_sends_the_command(server: Server, rig: tuple[dict[str, Any], str]) -> None:
    td, _ = rig
    invoke = _form(td["actions"]["set_sample_rate"], "invokeaction")
    body = {"name": "set_sample_rate", "args": {"value": 20}, "queue": True, "wait": False}
    with server.admin as admin:
        r = admin.request(invoke["htv:methodName"], invoke["href"], json=body)
        assert r.status_code == 202, r.text
        command = admin.get(f"{invoke['href']}/{r.json()['id']}").json()
    assert (command["name"], command["args"], command["state"]) == (
        "set_sample_rate",
        {"value": 20},
        "pending",
    )
    # The input schema says what the server checks: 500 is above the maximum.
    assert td["actions"]["set_sample_rate"]["input"]["properties"]["value"]["maximum"] == 100
    with server.admin as admin:
        r = admin.post(invoke["href"], json={**body, "args": {"value": 500}})
    assert r.status_code == 422 and "maximum 100" in r.json()["detail"]


async def test_observeproperty_is_the_live_websocket(
    server: Server, rig: tuple[dict[str, Any], str]
) -> None:
    td, device_token = rig
    observe = _form(td["properties"][ANGLE], "observeproperty")
    assert observe["href"] == server.url.replace("http://", "ws://") + "/api/v1/live"
    slug = td["links"][0]["href"].rsplit("/", 1)[1]
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    # A deadline so that a missing message fails the test instead of hanging it.
    async with asyncio.timeout(60), connect(observe["href"], additional_headers=headers) as ws:
        assert json.loads(await ws.recv())["type"] == "welcome"
        await ws.send(json.dumps({"op": "subscribe", "id": "a", "twin": slug, "signals": [ANGLE]}))
        subscribed = json.loads(await ws.recv())
        assert subscribed["type"] == "subscribed", subscribed
        with server.client(device_token) as device:
            sample = {"seq": 2, "samples": [{"values": {ANGLE: 0.5}}]}
            assert device.post("/api/v1/device/samples", json=sample).status_code == 200

        async def next_samples() -> dict[str, Any]:
            while True:
                message = json.loads(await ws.recv())
                if message["type"] == "samples":
                    return dict(message)

        message = await next_samples()
    assert message["samples"][0]["values"] == {ANGLE: 0.5}


def test_no_mqtt_form_for_the_embedded_listener(rig: tuple[dict[str, Any], str]) -> None:
    td, _ = rig
    hrefs = [f["href"] for f in td["properties"][ANGLE]["forms"]]
    assert not [h for h in hrefs if h.startswith("mqtt")]
    topic = next(link for link in td["links"] if link["href"].startswith("mqtt://"))
    assert topic["mqv:topic"].endswith("/{device}/telemetry")
