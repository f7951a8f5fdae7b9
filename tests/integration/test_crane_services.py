"""The Ilmatar crane's example services on random loopback ports, used with real clients:
asyncua for OPC UA and httpx for the HTTP services."""

from __future__ import annotations

import asyncio
import hashlib
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from datetime import datetime
from typing import Any

import httpx
import pytest
import pytest_asyncio
from asyncua import ua
from asyncua.client.client import Client
from asyncua.common.node import Node
from asyncua.ua.uaerrors import BadOutOfRange, BadUserAccessDenied

from ilmatar_crane import Crane, CranePorts, CraneSettings, start_crane
from ilmatar_crane.settings import OPCUA_NAMESPACE
from tests.integration._cad_checks import assert_closed_outward_mesh, assert_step_file
from twinlink_demo.crane_gateway import (
    HEALTH_PATHS,
    gateway_auth,
    gateway_base_urls,
    gateway_password_auth,
)

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]

FREE_PORTS = CranePorts(opcua=0, historian=0, bridge=0, cad=0, sensors=0)
SETTINGS = CraneSettings(autopilot=False, historian_period_s=0.1)
DEADLINE_S = 15.0


async def eventually(check: Callable[[], Awaitable[bool]], what: str) -> None:
    """Poll `check` until it holds; fail after DEADLINE_S."""
    loop = asyncio.get_running_loop()
    deadline = loop.time() + DEADLINE_S
    while not await check():
        if loop.time() > deadline:
            raise AssertionError(f"gave up waiting for {what}")
        await asyncio.sleep(0.05)


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def crane() -> AsyncIterator[Crane]:
    crane = await start_crane(ports=FREE_PORTS, settings=SETTINGS)
    try:
        yield crane
    finally:
        await crane.stop()


@pytest.fixture
def short_lived(crane: Crane) -> Iterator[Crane]:
    """The crane, issuing access tokens that last one second for the test's duration."""
    before = (crane.historian.token_ttl_s, crane.sensors.token_ttl_s)
    crane.historian.token_ttl_s = crane.sensors.token_ttl_s = 1.0
    try:
        yield crane
    finally:
        crane.historian.token_ttl_s, crane.sensors.token_ttl_s = before


def bridge(crane: Crane, key: str | None = None) -> httpx.AsyncClient:
    key = crane.credentials.bridge_api_key if key is None else key
    return httpx.AsyncClient(base_url=crane.urls["bridge"], headers={"X-API-Key": key})


def cad(crane: Crane, token: str | None = None) -> httpx.AsyncClient:
    headers = {"Authorization": f"Bearer {token or crane.credentials.cad_token}"}
    return httpx.AsyncClient(base_url=crane.urls["cad"], headers=headers)


async def historian_token(http: httpx.AsyncClient, crane: Crane) -> str:
    creds = crane.credentials
    r = await http.post(
        "login", json={"username": creds.historian_username, "password": creds.historian_password}
    )
    assert r.status_code == 200, r.text
    data = r.json()["data"]
    assert data["expires_in"] == crane.historian.token_ttl_s
    return str(data["token"])


async def sensor_token(crane: Crane, **form: str) -> httpx.Response:
    creds = crane.credentials
    basic = httpx.BasicAuth(creds.sensors_client_id, creds.sensors_client_secret)
    async with httpx.AsyncClient(auth=None if "client_id" in form else basic) as http:
        return await http.post(
            crane.root_url("sensors") + "oauth/token",
            data={"grant_type": "client_credentials", **form},
        )


def assert_error(r: httpx.Response, status: int, error: str | None = None) -> dict[str, Any]:
    assert r.status_code == status, r.text
    body: dict[str, Any] = r.json()
    assert isinstance(body["error"], str)
    assert error is None or body["error"] == error, body
    return body


# -- OPC UA server and its HTTP bridge --------------------------------------------------------


async def crane_node(client: Client, path: str) -> Node:
    ns = await client.get_namespace_index(OPCUA_NAMESPACE)
    parts = ["Ilmatar", *path.split(".")]
    return await client.nodes.objects.get_child([f"{ns}:{p}" for p in parts])


async def test_opc_ua_server_serves_values_units_and_checked_setpoints(crane: Crane) -> None:
    client = Client(crane.urls["opcua"], timeout=10)
    client.session_timeout = 600_000
    async with client:
        position = await crane_node(client, "Bridge.Position")
        setpoint = await crane_node(client, "Bridge.SpeedSetpoint")
        start = await position.read_value()
        assert start == pytest.approx(crane.plant.bridge.position, abs=0.01)
        units = await position.get_child("0:EngineeringUnits")
        assert (await units.read_value()).DisplayName.Text == "m"
        eu_range = await (await setpoint.get_child("0:EURange")).read_value()
        assert (eu_range.Low, eu_range.High) == (-0.5, 0.5)

        with pytest.raises(BadUserAccessDenied):
            await position.write_value(ua.Variant(1.0, ua.VariantType.Double))
        with pytest.raises(BadOutOfRange):
            await setpoint.write_value(ua.Variant(0.9, ua.VariantType.Double))
        assert crane.plant.bridge.setpoint == 0.0

        await setpoint.write_value(ua.Variant(-0.3, ua.VariantType.Double))
        assert crane.plant.bridge.setpoint == -0.3

        async def moved() -> bool:
            return bool(await position.read_value() < start - 0.1)

        await eventually(moved, "the bridge position to fall over OPC UA")
        await setpoint.write_value(ua.Variant(0.0, ua.VariantType.Double))


async def test_a_setpoint_written_through_the_bridge_moves_the_crane(crane: Crane) -> None:
    async with bridge(crane) as http:
        listing = (await http.get("variables")).json()["variables"]
        by_name = {v["name"]: v for v in listing}
        assert by_name["Hook.Load"]["unit"] == "kg"
        assert by_name["Trolley.SpeedSetpoint"]["writable"] is True
        assert by_name["Trolley.Position"]["writable"] is False
        assert all(datetime.fromisoformat(v["timestamp"]) for v in listing)
        start = by_name["Trolley.Position"]["value"]

        r = await http.put("variables/Trolley.SpeedSetpoint", json={"value": 0.4})
        assert r.status_code == 200, r.text
        assert r.json()["value"] == 0.4
        assert crane.plant.trolley.setpoint == 0.4

        async def moved() -> bool:
            r = await http.get("variables/Trolley.Position")
            return bool(r.json()["value"] > start + 0.1)

        await eventually(moved, "the trolley to move")
        assert crane.plant.trolley.position > start + 0.1
        assert (await http.put("variables/Trolley.SpeedSetpoint", json={"value": 0})).is_success


async def test_the_bridge_refuses_bad_writes_and_missing_keys(crane: Crane) -> None:
    async with bridge(crane) as http:
        assert_error(
            await http.put("variables/Hoist.Position", json={"value": 1}), 422, "read_only"
        )
        too_fast = await http.put("variables/Hoist.SpeedSetpoint", json={"value": 0.2})
        assert "between -0.15 and 0.15" in assert_error(too_fast, 422, "out_of_range")["detail"]
        for body in ({"value": True}, {"value": "fast"}, {}, [1]):
            r = await http.put("variables/Hoist.SpeedSetpoint", json=body)
            assert r.status_code == 422, body
        assert_error(await http.get("variables/Hoist.Colour"), 404, "not_found")
        assert crane.plant.hoist.setpoint == 0.0
    for key in ("", "wrong-key"):
        async with bridge(crane, key) as http:
            assert_error(await http.get("variables"), 401, "unauthorized")
            health = await http.get(crane.root_url("bridge") + "health")
            assert health.json()["status"] == "ok"


# -- historian --------------------------------------------------------------------------------


async def test_historian_custom_login_and_time_series(crane: Crane) -> None:
    async with httpx.AsyncClient(base_url=crane.urls["historian"]) as http:
        bad = await http.post("login", json={"username": "crane", "password": "guess"})
        assert_error(bad, 401, "invalid_credentials")
        logins = crane.historian.logins
        token = await historian_token(http, crane)
        assert crane.historian.logins == logins + 1
        # Bearer is not this service's scheme: the token goes in "Authorization: Token ...".
        assert_error(await http.get("signals", headers={"Authorization": f"Bearer {token}"}), 401)
        http.headers["Authorization"] = f"Token {token}"
        signals = {s["name"]: s["unit"] for s in (await http.get("signals")).json()["data"]}
        assert signals["hoist_position"] == "m" and signals["hook_load"] == "kg"

        async def recorded() -> bool:
            r = await http.get("timeseries", params={"signal": "hoist_position"})
            return len(r.json()["data"]["points"]) >= 5

        await eventually(recorded, "five samples")
        body = (await http.get("timeseries", params={"signal": "hoist_position"})).json()["data"]
        points = body["points"]
        assert body["unit"] == "m" and not body["truncated"]
        times = [p["time"] for p in points]
        assert times == sorted(times)
        assert all(0 <= p["value"] <= 8 for p in points)

        middle = points[len(points) // 2]["time"]
        since = await http.get("timeseries", params={"signal": "hoist_position", "from": middle})
        assert since.json()["data"]["points"][0]["time"] == middle
        until = datetime.fromisoformat(middle).timestamp()
        r = await http.get("timeseries", params={"signal": "hoist_position", "to": str(until)})
        assert r.json()["data"]["points"][-1]["time"] == middle
        params = {"signal": "hoist_position", "from": times[0], "to": times[3], "limit": "2"}
        page = (await http.get("timeseries", params=params)).json()["data"]
        assert [p["time"] for p in page["points"]] == times[:2]
        assert page["truncated"] and page["next_from"] == times[2]

        assert_error(await http.get("timeseries", params={"signal": "rope_wear"}), 404)
        for bad_params in ({"from": "yesterday"}, {"limit": "0"}, {"from": "2", "to": "1"}):
            r = await http.get("timeseries", params={"signal": "hook_load", **bad_params})
            assert_error(r, 422, "invalid_query")
        health = crane.root_url("historian") + "health"
        assert (await http.get(health, headers={"Authorization": ""})).status_code == 200


async def test_historian_tokens_expire(short_lived: Crane) -> None:
    async with httpx.AsyncClient(base_url=short_lived.urls["historian"]) as http:
        token = await historian_token(http, short_lived)
        http.headers["Authorization"] = f"Token {token}"
        assert (await http.get("signals")).status_code == 200

        async def expired() -> bool:
            return (await http.get("signals")).status_code == 401

        await eventually(expired, "the historian token to expire")
        fresh = await historian_token(http, short_lived)
        assert (await http.get("signals", headers={"Authorization": f"Token {fresh}"})).is_success


# -- CAD store --------------------------------------------------------------------------------


async def test_cad_store_lists_and_serves_valid_models(crane: Crane) -> None:
    async with cad(crane) as http:
        files = (await http.get("files")).json()["files"]
        names = {f["name"]: f for f in files}
        assert set(names) == {
            "ilmatar-main-girder.stl",
            "ilmatar-trolley.stl",
            "ilmatar-hook-block.stl",
            "ilmatar-main-girder.step",
        }
        for entry in files:
            r = await http.get(f"files/{entry['name']}")
            assert r.status_code == 200
            assert r.headers["content-type"] == entry["media_type"]
            assert len(r.content) == entry["size"]
            assert hashlib.sha256(r.content).hexdigest() == entry["sha256"]
            if entry["name"].endswith(".stl"):
                assert entry["media_type"] == "model/stl"
                assert_closed_outward_mesh(r.text)
            else:
                assert entry["media_type"] == "model/step"
                assert_step_file(r.text)


async def test_cad_store_ranges_head_traversal_and_auth(crane: Crane) -> None:
    name = "ilmatar-trolley.stl"
    async with cad(crane) as http:
        whole = (await http.get(f"files/{name}")).content
        part = await http.get(f"files/{name}", headers={"Range": "bytes=100-199"})
        assert part.status_code == 206
        assert part.headers["content-range"] == f"bytes 100-199/{len(whole)}"
        assert part.content == whole[100:200]
        head = await http.head(f"files/{name}")
        assert head.status_code == 200 and head.content == b""
        assert int(head.headers["content-length"]) == len(whole)
        assert_error(await http.get("files/no-such-part.stl"), 404, "not_found")
        for sneaky in ("..%2F..%2Fetc%2Fpasswd", "%2e%2e%2fsecret", ".hidden", "sub%2Fdir.stl"):
            r = await http.get(f"files/{sneaky}")
            assert r.status_code in (400, 404), sneaky
            assert_error(r, r.status_code)
    for token in ("", "not-the-token"):
        async with cad(crane, token) as http:
            headers = {} if token else {"Authorization": ""}
            r = await http.get(f"files/{name}", headers=headers)
            assert_error(r, 401, "unauthorized")
            assert r.headers["www-authenticate"].startswith("Bearer")


# -- sensor manager ---------------------------------------------------------------------------


async def test_sensor_manager_oauth2_grants(crane: Crane) -> None:
    creds = crane.credentials
    issued = crane.sensors.tokens_issued
    basic = await sensor_token(crane)
    in_form = await sensor_token(
        crane, client_id=creds.sensors_client_id, client_secret=creds.sensors_client_secret
    )
    password = await sensor_token(
        crane, grant_type="password", username=creds.sensors_username,
        password=creds.sensors_password,
    )  # fmt: skip
    for r in (basic, in_form, password):
        assert r.status_code == 200, r.text
        body = r.json()
        assert body["token_type"] == "Bearer" and body["expires_in"] == 300
        assert r.headers["cache-control"] == "no-store"
    assert crane.sensors.tokens_issued == issued + 3

    wrong = await sensor_token(crane, client_id=creds.sensors_client_id, client_secret="nope")
    assert wrong.status_code == 401 and wrong.json()["error"] == "invalid_client"
    bad_user = await sensor_token(crane, grant_type="password", username="x", password="y")
    assert bad_user.status_code == 400 and bad_user.json()["error"] == "invalid_grant"
    unknown = await sensor_token(crane, grant_type="authorization_code")
    assert unknown.json()["error"] == "unsupported_grant_type"
    assert crane.sensors.tokens_issued == issued + 3


async def test_sensor_manager_resources(crane: Crane) -> None:
    token = (await sensor_token(crane)).json()["access_token"]
    headers = {"Authorization": f"Bearer {token}"}
    async with httpx.AsyncClient(base_url=crane.urls["sensors"], headers=headers) as http:
        sensors = {s["id"]: s for s in (await http.get("sensors")).json()["sensors"]}
        assert {s["type"] for s in sensors.values()} == {"laser_distance", "accelerometer_3axis"}
        assert len(sensors) == 3
        laser = (await http.get("sensors/trolley-laser/latest")).json()
        assert laser["value"] == pytest.approx(crane.plant.trolley.position, abs=0.05)
        hook = (await http.get("sensors/hook-accelerometer/latest")).json()
        assert hook["value"]["z"] == pytest.approx(9.81, abs=0.5)

        r = await http.patch("sensors/hook-accelerometer", json={"sample_rate_hz": 200})
        assert r.status_code == 200 and r.json()["sample_rate_hz"] == 200
        assert (await http.get("sensors/hook-accelerometer")).json()["sample_rate_hz"] == 200
        for bad in ({"sample_rate_hz": 0}, {"sample_rate_hz": 5000}, {"sample_rate_hz": "x"},
                    {"status": "broken"}, {"id": "other"}, {"name": ""}):  # fmt: skip
            r = await http.patch("sensors/bridge-laser", json=bad)
            assert_error(r, 422, "invalid_value")
        assert (await http.get("sensors/bridge-laser")).json()["sample_rate_hz"] == 10
        await http.patch("sensors/bridge-laser", json={"status": "inactive"})
        assert_error(await http.get("sensors/bridge-laser/latest"), 409, "sensor_inactive")
        await http.patch("sensors/bridge-laser", json={"status": "active"})
        assert_error(await http.get("sensors/crane-camera"), 404, "not_found")

        r = await http.get("sensors", headers={"Authorization": "Bearer forged"})
        assert_error(r, 401)
        assert 'error="invalid_token"' in r.headers["www-authenticate"]


async def test_sensor_tokens_expire(short_lived: Crane) -> None:
    token = (await sensor_token(short_lived)).json()["access_token"]
    headers = {"Authorization": f"Bearer {token}"}
    async with httpx.AsyncClient(base_url=short_lived.urls["sensors"], headers=headers) as http:
        assert (await http.get("sensors")).status_code == 200
        last: list[httpx.Response] = []

        async def expired() -> bool:
            last[:] = [await http.get("sensors")]
            return last[0].status_code == 401

        await eventually(expired, "the sensor token to expire")
        challenge = last[0].headers["www-authenticate"]
        assert challenge.startswith("Bearer") and 'error="invalid_token"' in challenge


# -- the gateway mapping, the DT documents, stopping and the CLI ------------------------------


async def test_gateway_settings_work_against_the_services(crane: Crane) -> None:
    """Sign in to each service as the gateway would with `gateway_auth`, then GET its health
    path below its base URL."""
    auth = gateway_auth(crane)
    assert (
        set(auth)
        == set(HEALTH_PATHS)
        == {
            "historian",
            "opc-ua-server",
            "cad-store",
            "sensor-manager",
        }
    )
    urls = {name: base + HEALTH_PATHS[name] for name, base in gateway_base_urls(crane).items()}
    async with httpx.AsyncClient() as http:
        login = auth["historian"]
        answer = (await http.post(login["login_url"], json=login["body"])).json()
        token = answer["data"]["token"]  # token_path "data.token"
        header = {login["header"]: login["template"].format(token=token)}
        assert (await http.get(urls["historian"], headers=header)).is_success
        key = auth["opc-ua-server"]
        api_key = {key["name"]: key["value"]}
        assert (await http.get(urls["opc-ua-server"], headers=api_key)).is_success
        bearer = {"Authorization": f"Bearer {auth['cad-store']['token']}"}
        assert (await http.get(urls["cad-store"], headers=bearer)).is_success
        for grant in (auth["sensor-manager"], gateway_password_auth(crane)):
            form = {"grant_type": grant["method"].removeprefix("oauth2_")}
            if "username" in grant:
                form |= {"username": grant["username"], "password": grant["password"]}
            client = httpx.BasicAuth(grant["client_id"], grant["client_secret"])
            got = await http.post(grant["token_url"], data=form, auth=client)
            bearer = {"Authorization": f"Bearer {got.json()['access_token']}"}
            assert (await http.get(urls["sensor-manager"], headers=bearer)).is_success
