"""An OPC UA connector made through the API of a real server, against the simulated crane's
real asyncua server (with a user and password) running in a thread of the test: its secret is
never shown or logged, its values reach the twin, a twin command writes a node."""

from __future__ import annotations

import asyncio
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import orjson
import pytest
import yaml

from ilmatar_crane.opcua import CraneOpcUaServer, OpcUaAccess
from ilmatar_crane.plant import CranePlant
from tests.conftest import Server, free_port
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._util import apply, assert_problem, poll_until, twin_doc, unique
from tests.integration.test_opcua_security import write_identity

pytestmark = pytest.mark.integration

PASSWORD = "crane-op-7f3a9c"
NS = "ns=2;s=Ilmatar"


class Crane:
    def __init__(self) -> None:
        self.plant = CranePlant()
        self.server = CraneOpcUaServer(self.plant, OpcUaAccess(users={"operator": PASSWORD}))
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self.loop.run_forever, daemon=True)
        self.url = ""

    def __enter__(self) -> Crane:
        self.thread.start()
        port = free_port()
        self.run(self.server.start("127.0.0.1", port))
        self.url = f"opc.tcp://127.0.0.1:{port}"
        return self

    def __exit__(self, *_: object) -> None:
        self.run(self.server.stop())
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(10)
        self.loop.close()

    def run(self, coro: Any) -> Any:
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(30)


@pytest.fixture(scope="module")
def crane() -> Iterator[Crane]:
    with Crane() as c:
        yield c


def _config(crane: Crane, **extra: Any) -> dict[str, Any]:
    return {
        "url": crane.url,
        "username": "operator",
        "password": PASSWORD,
        "reconnect_initial_s": 0.1,
        "reconnect_max_s": 0.5,
        "signals": [
            {"node": f"{NS}.Bridge.Position", "signal": "bridge_position"},
            {"node": f"{NS}.Hook.Load", "signal": "load"},
        ],
        "commands": {"set_bridge_speed": {"node": f"{NS}.Bridge.SpeedSetpoint"}},
        **extra,
    }


def test_an_opcua_connector_made_by_api(server: Server, crane: Crane) -> None:
    slug = unique("plc")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Crane", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": "plc", "kind": "opcua", "config": _config(crane)},
        )
        assert r.status_code == 201, r.text
        assert PASSWORD not in r.text
        assert r.json()["config"]["password_set"] is True and "password" not in r.json()["config"]

        def connected() -> dict[str, Any] | None:
            view = admin.get(f"/api/v1/twins/{slug}/connectors/plc").json()
            return view if view["status"]["state"] == "connected" else None

        poll_until(connected, "the connector to connect")

        def stored() -> bool:
            streams = admin.get(f"/api/v1/twins/{slug}/streams").json()["streams"]
            return any(s["count"] > 0 for s in streams)

        poll_until(stored, "the crane's values in the twin's history")
        r = admin.post(
            f"/api/v1/twins/{slug}/commands",
            json={"name": "set_bridge_speed", "args": {"value": 0.25}, "device": "plc"},
        )
        assert r.status_code == 200, r.text
        assert r.json()["state"] == "succeeded", r.json()
        assert crane.plant.bridge.setpoint == pytest.approx(0.25)

        # A change of another setting keeps the password; a wrong one shows in the status.
        r = admin.patch(f"/api/v1/twins/{slug}/connectors/plc", json={"config": {"stream": "plc"}})
        assert r.status_code == 200 and r.json()["config"]["password_set"] is True
        poll_until(connected, "the connector to connect again with the kept password")
        r = admin.patch(
            f"/api/v1/twins/{slug}/connectors/plc", json={"config": {"password": "wrong-one"}}
        )
        assert r.status_code == 200, r.text

        def refused() -> str | None:
            status = admin.get(f"/api/v1/twins/{slug}/connectors/plc").json()["status"]
            return status["last_error"] if status["state"] == "error" else None

        assert "password" in poll_until(refused, "the wrong password to be reported")
        r = admin.post(f"/api/v1/twins/{slug}/connectors", json={
            "name": "bad", "kind": "opcua", "config": {"url": "http://not-opc"}})  # fmt: skip
        assert "url" in assert_problem(r, 422)["detail"]
    assert PASSWORD not in server.log() and "wrong-one" not in server.log()
    # asyncua's own warning about each refused attempt is a JSON line like the server's.
    asyncua = [line for line in server.log().splitlines() if "asyncua" in line]
    assert asyncua, server.log()
    assert all(orjson.loads(line)["logger"].startswith("asyncua.") for line in asyncua)


def test_a_client_key_of_another_certificate_is_refused_at_create(
    server: Server, crane: Crane, tmp_path: Path
) -> None:
    slug = unique("plc")
    cert, _ = write_identity(tmp_path, "client", "urn:example:client")
    _, other_key = write_identity(tmp_path, "other", "urn:example:other")
    config = {
        **_config(crane),
        "security_policy": "Basic256Sha256",
        "certificate": str(cert),
        "private_key": str(other_key),
    }
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Crane", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": "plc", "kind": "opcua", "config": config},
        )
        detail = assert_problem(r, 422)["detail"]
        assert (
            f"private_key {other_key} does not belong to certificate {cert}: their public keys "
            "differ"
        ) in detail
        assert_problem(admin.get(f"/api/v1/twins/{slug}/connectors/plc"), 404)
        assert admin.get(f"/api/v1/twins/{slug}/devices").json()["devices"] == []


def test_each_node_not_subscribed_is_shown_by_api_and_cli(
    server: Server, crane: Crane, tmp_path: Path
) -> None:
    slug = unique("plc")
    config = _config(crane)
    config["signals"] = [
        *config["signals"],
        {"node": f"{NS}.Hook.Weight", "signal": "weight"},
        {"node": "/2:Ilmatar/2:Hook/2:Mass", "signal": "mass"},
    ]
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Crane", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": "plc", "kind": "opcua", "config": config},
        )
        assert r.status_code == 201, r.text

        def connected() -> dict[str, Any] | None:
            status = admin.get(f"/api/v1/twins/{slug}/connectors/plc").json()["status"]
            return status if status["state"] == "connected" else None

        status = poll_until(connected, "the connector to connect")
    assert status["monitored"] == 2
    assert status["failed_nodes"] == [
        {"signal": "weight", "node": f"{NS}.Hook.Weight",
         "reason": f"the server does not monitor {NS}.Hook.Weight (BadNodeIdUnknown)"},
        {"signal": "mass", "node": "/2:Ilmatar/2:Hook/2:Mass",
         "reason": "the server has no node at /2:Ilmatar/2:Hook/2:Mass"},
    ]  # fmt: skip
    assert status["failed_nodes_more"] == 0
    env = {"TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token,
           "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}  # fmt: skip
    shown = subprocess.run(
        [sys.executable, "-m", "twinlink", "connectors", "show", slug, "plc"],
        env=env, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL,
    )  # fmt: skip
    assert shown.returncode == 0, shown.stderr
    printed = yaml.safe_load(shown.stdout)["status"]
    assert printed["failed_nodes"] == status["failed_nodes"]
    with server.admin as admin:  # its session ends before the crane's server stops
        assert admin.delete(f"/api/v1/twins/{slug}/connectors/plc").status_code == 204
