"""The crane as `make demo` sets it up: its services behind the gateway, signed in with each
one's own method, reached with nothing but a platform token."""

from __future__ import annotations

import asyncio
import hashlib
import re
from collections.abc import AsyncIterator
from typing import Any

import httpx
import pytest
import pytest_asyncio

from ilmatar_crane import Crane, CranePorts, CraneSettings, start_crane
from ilmatar_crane.settings import PORT_NAMES
from tests.conftest import EXAMPLES, Server
from tests.integration._util import YAML_HEADERS
from twinlink_demo.crane import DemoCrane, plc_connector
from twinlink_demo.crane_gateway import HEALTH_PATHS, gateway_auth

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]

SLUG = "ilmatar-k16052"


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def crane() -> AsyncIterator[Crane]:
    crane = await start_crane(
        ports=CranePorts(opcua=0, historian=0, bridge=0, cad=0, sensors=0),
        settings=CraneSettings(autopilot=False, historian_period_s=0.1),
    )
    try:
        yield crane
    finally:
        await crane.stop()


def _documents_for(crane: Crane) -> bytes:
    """The crane's DT documents with its services' default ports replaced by the real ones,
    as `make demo` applies them when a default port is taken."""
    usual = CranePorts()
    moved = {name: (getattr(usual, name), getattr(crane.ports, name)) for name in PORT_NAMES}
    demo = DemoCrane(crane, moved)
    paths = sorted((EXAMPLES / "ilmatar").glob("ilmatar-*.yaml"))
    return "\n---\n".join(demo.documents(p.read_text("utf-8")) for p in paths).encode()


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def gateway(server: Server, crane: Crane) -> AsyncIterator[httpx.AsyncClient]:
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    async with httpx.AsyncClient(base_url=server.url, headers=headers, timeout=30) as client:
        r = await client.post("/api/v1/apply", content=_documents_for(crane), headers=YAML_HEADERS)
        assert r.status_code == 200, r.text
        for name, auth in gateway_auth(crane).items():  # what twinlink_demo.crane sends
            r = await client.patch(
                f"/api/v1/twins/{SLUG}/services/{name}",
                json={"auth": auth, "health_path": HEALTH_PATHS[name]},
            )
            assert r.status_code == 200, r.text
        yield client


async def test_every_crane_service_is_a_gateway_service_with_its_own_sign_in(
    gateway: httpx.AsyncClient, crane: Crane
) -> None:
    listed = (await gateway.get(f"/api/v1/twins/{SLUG}/services")).json()["services"]
    by_name = {s["name"]: s for s in listed}
    methods = {name: by_name[name]["auth"]["method"] for name in HEALTH_PATHS}
    assert methods == {
        "historian": "custom_login",
        "opc-ua-server": "api_key",
        "cad-store": "bearer",
        "sensor-manager": "oauth2_client_credentials",
    }
    assert by_name["historian"]["base_url"] == crane.urls["historian"]
    secrets = [crane.credentials.historian_password, crane.credentials.cad_token]
    assert not any(secret in str(listed) for secret in secrets)
    for name in HEALTH_PATHS:
        health = (await gateway.get(f"/api/v1/twins/{SLUG}/services/{name}/health")).json()
        assert health["status"] == "up", (name, health)


async def test_the_historian_answers_through_its_custom_login(
    gateway: httpx.AsyncClient, crane: Crane
) -> None:
    base = f"/twins/{SLUG}/services/historian"
    signals = (await gateway.get(f"{base}/signals")).json()["data"]
    assert "hoist_position" in {s["name"] for s in signals}
    logins = crane.historian.logins
    r = await gateway.get(f"{base}/timeseries", params={"signal": "hoist_position", "limit": 5})
    assert r.status_code == 200, r.text
    assert crane.historian.logins == logins  # the token is kept, not fetched per request


async def test_a_setpoint_written_through_the_gateway_moves_the_crane(
    gateway: httpx.AsyncClient, crane: Crane
) -> None:
    base = f"/twins/{SLUG}/services/opc-ua-server/variables"
    start = crane.plant.trolley.position
    r = await gateway.put(f"{base}/Trolley.SpeedSetpoint", json={"value": 0.3})
    assert r.status_code == 200, r.text
    deadline = asyncio.get_running_loop().time() + 15
    while crane.plant.trolley.position <= start + 0.01:
        assert asyncio.get_running_loop().time() < deadline, "the trolley did not move"
        await asyncio.sleep(0.05)
    await gateway.put(f"{base}/Trolley.SpeedSetpoint", json={"value": 0.0})
    got = (await gateway.get(f"{base}/Trolley.Position")).json()
    assert got["unit"] == "m"


async def test_cad_files_download_whole_and_in_ranges(gateway: httpx.AsyncClient) -> None:
    base = f"/twins/{SLUG}/services/cad-store/files"
    files: list[dict[str, Any]] = (await gateway.get(base)).json()["files"]
    stl = next(f for f in files if f["name"].endswith(".stl"))
    whole = await gateway.get(f"{base}/{stl['name']}")
    assert hashlib.sha256(whole.content).hexdigest() == stl["sha256"]
    part = await gateway.get(f"{base}/{stl['name']}", headers={"Range": "bytes=0-4"})
    assert part.status_code == 206 and part.content == whole.content[:5]


async def test_sensors_through_oauth2_and_the_audit_log(
    gateway: httpx.AsyncClient, server: Server, crane: Crane
) -> None:
    base = f"/twins/{SLUG}/services/sensor-manager/sensors"
    sensors = (await gateway.get(base)).json()["sensors"]
    assert {"bridge-laser"} <= {s["id"] for s in sensors}
    issued = crane.sensors.tokens_issued
    r = await gateway.patch(f"{base}/bridge-laser", json={"sample_rate_hz": 20})
    assert r.status_code == 200, r.text
    assert crane.sensors.tokens_issued == issued
    audit = (await gateway.get("/api/v1/gateway/audit", params={"twin": SLUG})).json()
    assert any(
        e["service"] == "sensor-manager" and e["method"] == "PATCH" and e["status"] == 200
        for e in audit["entries"]
    )
    assert not re.search(crane.credentials.sensors_client_secret, str(audit))


async def test_the_demos_opc_ua_connector_feeds_the_crane_twin(
    gateway: httpx.AsyncClient, crane: Crane
) -> None:
    r = await gateway.post(f"/api/v1/twins/{SLUG}/connectors", json=plc_connector(crane.opcua.url))
    assert r.status_code == 201, r.text
    try:
        deadline = asyncio.get_running_loop().time() + 20
        signals: set[str] = set()
        while not {"bridge_position", "load"} <= signals:
            assert asyncio.get_running_loop().time() < deadline, signals
            streams = (await gateway.get(f"/api/v1/twins/{SLUG}/streams")).json()["streams"]
            signals = {s["name"] for st in streams for s in st["signals"]}
            await asyncio.sleep(0.05)  # polling the real state
        r = await gateway.post(
            f"/api/v1/twins/{SLUG}/commands",
            json={"name": "set_hoist_speed", "args": {"value": -0.05}, "device": "plc"},
        )
        assert r.status_code == 200 and r.json()["state"] == "succeeded", r.text
        assert crane.plant.hoist.setpoint == pytest.approx(-0.05)
    finally:
        await gateway.delete(f"/api/v1/twins/{SLUG}/connectors/plc")
