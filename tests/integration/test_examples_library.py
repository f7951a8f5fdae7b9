"""The library examples (examples/library) do what their README says: the Tingen package
deploys a running twin whose FMU computes on the device's samples, the crane's package puts
its services behind the gateway as the demo does, and the DTaaS-style folder's lifecycle
scripts run its batch simulation, by hand and as deployment runs."""

from __future__ import annotations

import asyncio
import json
import math
import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import httpx
import pytest
import yaml

from ilmatar_crane import Crane, CranePorts, CraneSettings, start_crane
from ilmatar_crane.settings import DemoCredentials
from tests.conftest import EXAMPLES, FmuFiles, Server, start_server, stop_server
from tests.integration._processors import wait_for
from tests.integration._util import poll_until
from twinlink.client._tar import folder_files, pack
from twinlink_demo.crane import plc_connector
from twinlink_demo.crane_gateway import HEALTH_PATHS, gateway_auth

pytestmark = pytest.mark.integration

LIBRARY = EXAMPLES / "library"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def push(server: Server, kind: str, name: str, source: Path, **params: Any) -> dict[str, Any]:
    """Push a folder (its contents, as tar) or one file to common/<kind>/<name>, as 1.0.0."""
    if source.is_dir():
        body, query = b"".join(pack(folder_files(source))), {"format": "tar"}
    else:
        body, query = source.read_bytes(), {"format": "file", "filename": source.name}
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/library/common/{kind}/{name}/versions",
            params={**query, "tag": ["1.0.0", "latest"], **params},
            content=body,
        )
    assert r.status_code in (200, 201), r.text
    return r.json()["version"]  # type: ignore[no-any-return]


def deploy(server: Server, package: str, name: str, **body: Any) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post("/api/v1/deployments", json={"package": package, "name": name, **body})
    assert r.status_code == 201, r.text
    return r.json()  # type: ignore[no-any-return]


@pytest.fixture(scope="module")
def tingen_pushed(server: Server, fmu_files: FmuFiles, tmp_path_factory: pytest.TempPathFactory
                  ) -> dict[str, Any]:  # fmt: skip
    """The three Tingen assets in `common`, as the README pushes them; the FMU's version."""
    fmu = tmp_path_factory.mktemp("fmu") / "tingen.fmu"
    shutil.copyfile(fmu_files("tingen"), fmu)
    beam = push(server, "models", "tingen-beam", fmu)
    push(server, "tools", "tingen-sim", LIBRARY / "tingen-sim")
    push(server, "twins", "tingen-rig", LIBRARY / "tingen-rig")
    return beam


def streams(server: Server, slug: str) -> dict[str, dict[str, Any]]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/streams")
    assert r.status_code == 200, r.text
    return {s["name"]: s for s in r.json()["streams"]}


def finished_run(server: Server, name: str, phase: str) -> tuple[dict[str, Any], str]:
    """Run a phase of the deployment and wait for it to end; the run and its log."""
    with server.admin as admin:
        r = admin.post(f"/api/v1/deployments/{name}/runs", json={"phase": phase})
        assert r.status_code == 202, r.text
        run_id = r.json()["id"]

        def ended() -> dict[str, Any] | None:
            run: dict[str, Any] = admin.get(f"/api/v1/runs/{run_id}").json()
            return run if run["state"] not in ("queued", "running") else None

        run = poll_until(ended, f"the {phase} run of {name} to end", 60)
        return run, admin.get(f"/api/v1/runs/{run_id}/log").text


def test_the_tingen_package_runs_its_rig_and_fmu(
    server: Server, tingen_pushed: dict[str, Any]
) -> None:
    made = deploy(server, "tingen-rig@1.0.0", "rig-a", parameters={"zeta": 1.0}, start=True)
    planned = {(c["type"], c["name"]) for c in made["plan"]["create"]}
    assert {("twin", "rig-a"), ("device", "tingenSAP"), ("processor", "fmu")} <= planned
    assert set(made["device_tokens"]) == {"tingenSAP"}
    view = wait_for(server, "rig-a", "fmu", lambda p: p["state"] == "running")
    assert view["params"]["fmu"] == (
        f"lib:common/models/tingen-beam@{tingen_pushed['digest']}#tingen.fmu"
    )
    assert view["params"]["parameters"] == {"zeta": 1.0}  # the parameter, a number
    with server.admin as admin:
        twin = admin.get("/api/v1/twins/rig-a").json()
    assert twin["document"]["interface"]["default_device"] == "tingenSAP"
    # The execute phase runs the simulated rig as tingenSAP; the FMU computes on its force.
    poll_until(lambda: streams(server, "rig-a").get("fmu", {}).get("samples", 0) >= 50,
               "the FMU's output on the rig's samples", 60)  # fmt: skip
    telemetry = streams(server, "rig-a")["telemetry"]
    assert {"Cantilever_Angle_radians", "Input_F_in"} <= {s["name"] for s in telemetry["signals"]}
    run, log = finished_run(server, "rig-a", "analyze")
    assert (run["state"], run["exit_code"]) == ("succeeded", 0), log
    assert "stream telemetry:" in log and "fmu.theta (last minute):" in log, log
    with server.admin as admin:
        assert admin.post("/api/v1/deployments/rig-a/stop").status_code == 200
        runs = admin.get("/api/v1/deployments/rig-a/runs").json()["runs"]
    [execute] = [r for r in runs if r["phase"] == "execute"]
    assert execute["state"] != "running", execute  # the rig ended with the deployment's stop
    assert wait_for(server, "rig-a", "fmu", lambda p: p["state"] == "stopped")


def test_a_new_fmu_version_reaches_a_running_deployment_with_its_parameters_kept(
    server: Server, tingen_pushed: dict[str, Any], fmu_files: FmuFiles, tmp_path: Path
) -> None:
    """Reconfigure to a package version whose FMU is another version: the plan says the
    processor changes and nothing else, the processor runs the new FMU, and the parameters
    given at create stay."""
    made = deploy(server, "tingen-rig@1.0.0", "rig-c", parameters={"zeta": 1.2}, start=True)
    assert made["deployment"]["parameters"]["zeta"] == 1.2
    wait_for(server, "rig-c", "fmu", lambda p: p["state"] == "running")
    # The beam as FMI 3 (another build, another digest) as 1.1.0, and the package naming it.
    fmu3 = tmp_path / "tingen.fmu"
    shutil.copyfile(fmu_files("tingen3"), fmu3)
    package = tmp_path / "tingen-rig"
    shutil.copytree(LIBRARY / "tingen-rig", package)
    twin_yaml = package / "twin.yaml"
    text = twin_yaml.read_text()
    assert "tingen-beam@1.0.0" in text
    twin_yaml.write_text(text.replace("tingen-beam@1.0.0", "tingen-beam@1.1.0"))
    with server.admin as admin:
        for kind, name, query, body in (
            ("models", "tingen-beam", {"format": "file", "filename": "tingen.fmu"},
             fmu3.read_bytes()),
            ("twins", "tingen-rig", {"format": "tar"}, b"".join(pack(folder_files(package)))),
        ):  # fmt: skip
            query = {**query, "tag": "1.1.0", "latest": "false"}
            r = admin.post(f"/api/v1/library/common/{kind}/{name}/versions", params=query,
                           content=body)  # fmt: skip
            assert r.status_code == 201, r.text
        new_beam = admin.get("/api/v1/library/common/models/tingen-beam/versions/1.1.0").json()
        assert new_beam["digest"] != tingen_pushed["digest"]
        change = {"package": "common/twins/tingen-rig@1.1.0"}
        r = admin.patch("/api/v1/deployments/rig-c", params={"dry_run": True}, json=change)
        assert r.status_code == 200, r.text
        plan = r.json()["plan"]
        assert [(u["type"], u["name"]) for u in plan["update"]] == [("processor", "fmu")], plan
        assert not plan["create"] and not plan["delete"], plan
        r = admin.patch("/api/v1/deployments/rig-c", json=change)
        assert r.status_code == 200, r.text
        deployment = admin.get("/api/v1/deployments/rig-c").json()
    assert deployment["parameters"] == {"zeta": 1.2, "sample_rate": 100}
    assert "tingen-rig@sha256:" in deployment["package"]
    pinned = f"lib:common/models/tingen-beam@{new_beam['digest']}#tingen.fmu"
    view = wait_for(server, "rig-c", "fmu",
                    lambda p: p["params"]["fmu"] == pinned and p["state"] == "running")  # fmt: skip
    assert view["params"]["parameters"] == {"zeta": 1.2}
    with server.admin as admin:
        r = admin.post("/api/v1/deployments/rig-c/terminate", json={"purge": True})
        assert r.status_code == 200, r.text
        # Nothing holds 1.1.0 any more: it goes, which leaves 1.0.0 to the last test.
        for kind, name in (("twins", "tingen-rig"), ("models", "tingen-beam")):
            r = admin.delete(f"/api/v1/library/common/{kind}/{name}/versions/1.1.0")
            assert r.status_code == 204, r.text


def test_a_deployed_tingen_leaves_nothing_held_once_terminated(
    server: Server, tingen_pushed: dict[str, Any]
) -> None:
    """The last of the Tingen tests: it deletes the FMU's version."""
    deploy(server, "common/twins/tingen-rig@1.0.0", "rig-b")
    beam = f"/api/v1/library/common/models/tingen-beam/versions/{tingen_pushed['digest']}"
    with server.admin as admin:
        assert admin.delete(beam).status_code == 409  # held by the deployments and processors
        for name in ("rig-a", "rig-b"):
            r = admin.post(f"/api/v1/deployments/{name}/terminate", json={"purge": True})
            assert r.status_code == 200, r.text
            assert admin.get(f"/api/v1/twins/{name}").status_code == 404
        r = admin.delete(beam)
        assert r.status_code == 204, r.text


def test_the_crane_package_sets_up_the_gateway_and_the_connector_as_the_demo_does() -> None:
    package = yaml.safe_load((LIBRARY / "ilmatar-crane" / "twin.yaml").read_text())
    # The demo's own settings, with the service URLs as the package's parameters.
    templated = SimpleNamespace(
        credentials=DemoCredentials(), root_url=lambda service: f"${{params.{service}_url}}"
    )
    auth = gateway_auth(templated)  # type: ignore[arg-type]
    services = {s["name"]: s for s in package["services"]}
    assert set(services) == set(HEALTH_PATHS) == set(auth)
    for name, service in services.items():
        assert service["auth"] == auth[name], name
        assert service["health_path"] == HEALTH_PATHS[name]
    assert package["connectors"] == [plc_connector("${params.opcua_url}")]


async def test_the_crane_package_reaches_the_cranes_services(server: Server) -> None:
    crane = await start_crane(
        ports=CranePorts(opcua=0, historian=0, bridge=0, cad=0, sensors=0),
        settings=CraneSettings(autopilot=False, historian_period_s=0.1),
    )
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    client = httpx.AsyncClient(base_url=server.url, headers=headers, timeout=30)
    try:
        await deploy_crane(server, crane, client)
    finally:  # the connector's OPC UA session ends before the crane's server
        await client.post("/api/v1/deployments/crane-a/terminate", json={"purge": True})
        await client.aclose()
        await crane.stop()


async def deploy_crane(server: Server, crane: Crane, client: httpx.AsyncClient) -> None:
    push(server, "twins", "ilmatar-crane", LIBRARY / "ilmatar-crane")
    roots = {name: crane.root_url(name) for name in ("historian", "bridge", "cad", "sensors")}
    parameters: dict[str, Any] = {f"{name}_url": url for name, url in roots.items()}
    parameters["opcua_url"] = crane.opcua.url
    body = {"package": "ilmatar-crane@1.0.0", "name": "crane-a", "parameters": parameters,
            "start": True}  # fmt: skip
    r = await client.post("/api/v1/deployments", json=body)
    assert r.status_code == 201, r.text
    for name in HEALTH_PATHS:  # each one's health needs its credentials
        r = await client.get(f"/api/v1/twins/crane-a/services/{name}/health")
        assert r.status_code == 200 and r.json()["status"] == "up", (name, r.text)
    r = await client.get("/twins/crane-a/services/historian/signals")
    assert r.status_code == 200, r.text
    for _ in range(1200):  # the connector reads the crane's OPC UA server
        plc = (await client.get("/api/v1/twins/crane-a/connectors/plc")).json()
        if plc["status"]["samples"] > 0:
            break
        await asyncio.sleep(0.05)  # polling the connector's real state
    assert plc["status"]["state"] == "connected", plc


def _phases(folder: Path, *phases: str) -> list[str]:
    out = []
    for phase in phases:
        done = subprocess.run(
            [str(folder / "lifecycle" / phase)], capture_output=True, text=True, timeout=60
        )
        assert done.returncode == 0, (phase, done.stdout, done.stderr)
        out.append(done.stdout)
    return out


def test_the_dtaas_folders_lifecycle_runs_by_hand(tmp_path: Path) -> None:
    folder = shutil.copytree(LIBRARY / "mass-spring-damper", tmp_path / "msd")
    _phases(folder, "create", "execute", "analyze")
    summary = json.loads((folder / "output" / "summary.json").read_text())
    config = json.loads((folder / "config.json").read_text())
    m, k, c = config["mass"], config["stiffness"], config["damping"]
    zeta = c / (2 * math.sqrt(k * m))
    # An underdamped step response: the overshoot and its time follow from zeta and omega.
    overshoot = 100 * math.exp(-math.pi * zeta / math.sqrt(1 - zeta**2))
    peak_time = math.pi / (math.sqrt(k / m) * math.sqrt(1 - zeta**2))
    assert math.isclose(summary["overshoot_percent"], overshoot, rel_tol=0.01), summary
    assert abs(summary["peak_time_s"] - peak_time) <= config["dt"] * config["output_every"]
    assert math.isclose(summary["end_position_m"], config["force"] / k, rel_tol=0.02)
    _phases(folder, "terminate", "clean")
    assert not (folder / "output").exists()


def test_the_dtaas_folder_imports_and_its_phases_run_as_deployment_runs(server: Server) -> None:
    env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token}
    folder = LIBRARY / "mass-spring-damper"
    args = ["lib", "import-dtaas", str(folder), "--scope", "common", "--tag", "1.0.0"]
    done = subprocess.run([sys.executable, "-m", "twinlink", *args], env=env,
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    deploy(server, "mass-spring-damper@1.0.0", "msd-a")
    run, log = finished_run(server, "msd-a", "execute")
    assert (run["state"], run["exit_code"]) == ("succeeded", 0), log
    assert "simulated 5 s in 501 rows" in log, log
    run, log = finished_run(server, "msd-a", "analyze")
    assert (run["state"], run["exit_code"]) == ("succeeded", 0), log
    assert "simulating first" not in log  # execute's results, in the deployment's folder
    overshoot = float(re.search(r"overshoot_percent: ([0-9.]+)", log)[1])  # type: ignore[index]
    assert math.isclose(overshoot, 100 * math.exp(-math.pi * 0.1 / math.sqrt(0.99)), rel_tol=0.01)
