"""Deployments end to end on a real server: a twin package pushed to the library, planned,
applied all or nothing, started (processors running), reconfigured (a changed processor
updated, an unchanged one left running in the same worker), stopped and terminated with
nothing left behind."""

from __future__ import annotations

import contextlib
import io
import sqlite3
import tarfile
from collections.abc import Iterator
from typing import Any

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._processors import T0, post, wait_for
from tests.integration._util import assert_problem, make_user, unique

pytestmark = pytest.mark.integration

# A package of two processors without FMUs: `smooth` takes its cut-off from a parameter,
# `sum` takes nothing from the parameters (a change of them leaves it alone).
TWIN_YAML = """\
description: a test rig with a filter
parameters:
  type: object
  properties:
    cutoff: {type: number, default: 5, exclusiveMinimum: 0}
    label: {type: string, default: rig}
    privacy: {enum: [public, private], default: public}
  additionalProperties: false
document:
  version: "1.0"
  privacy: ${params.privacy}
  name: ${params.label} ${deployment.name}
  description: deployed at ${twin.url}
devices:
  - {name: rig, description: the test rig}
processors:
  - name: smooth
    blueprint: lowpass
    source: telemetry
    params: {signals: [x], cutoff_hz: "${params.cutoff}", sample_rate_hz: 100}
  - name: sum
    blueprint: expression
    source: telemetry
    params: {outputs: {s: "x + 1"}}
"""


def tar_of(files: dict[str, str]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for path, text in files.items():
            data = text.encode()
            info = tarfile.TarInfo(path)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def push(c: httpx.Client, name: str, files: dict[str, str], tag: str = "1.0.0") -> str:
    r = c.post(
        f"/api/v1/library/me/twins/{name}/versions",
        params={"format": "tar", "tag": [tag, "latest"]},
        content=tar_of(files),
    )
    assert r.status_code in (200, 201), r.text
    return str(r.json()["version"]["digest"])


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture(scope="module")
def user(server: Server) -> str:
    token = make_user(server, "deployer")
    with server.client(token) as c:
        push(c, "rig", {"twin.yaml": TWIN_YAML})
    return token


def processors(c: httpx.Client, slug: str) -> dict[str, dict[str, Any]]:
    r = c.get(f"/api/v1/twins/{slug}/processors")
    assert r.status_code == 200, r.text
    return {p["name"]: p for p in r.json()["processors"]}


def deploy(c: httpx.Client, name: str, **body: Any) -> dict[str, Any]:
    r = c.post("/api/v1/deployments", json={"package": "rig@1.0.0", "name": name, **body})
    assert r.status_code == 201, r.text
    return r.json()  # type: ignore[no-any-return]


def test_a_dry_run_plans_and_changes_nothing(server: Server, user: str) -> None:
    name = unique("dry")
    with server.client(user) as c:
        r = c.post(
            "/api/v1/deployments",
            params={"dry_run": "true"},
            json={"package": "rig@1.0.0", "name": name, "parameters": {"cutoff": 2}},
        )
        assert r.status_code == 200, r.text
        plan = r.json()["plan"]
        assert [(e["type"], e["name"]) for e in plan["create"]] == [
            ("twin", name), ("device", "rig"), ("processor", "smooth"), ("processor", "sum"),
        ]  # fmt: skip
        smooth = plan["create"][2]["spec"]
        assert smooth["params"]["cutoff_hz"] == 2  # a number, as the schema has it
        assert plan["create"][0]["spec"]["name"] == f"rig {name}"
        assert_problem(c.get(f"/api/v1/twins/{name}"), 404)
        assert_problem(c.get(f"/api/v1/deployments/{name}"), 404)


def test_deploy_start_reconfigure_stop_terminate(server: Server, user: str) -> None:
    name = unique("rig")
    with server.client(user) as c:
        made = deploy(c, name, parameters={"cutoff": 4, "label": "Test"})
        deployment, tokens = made["deployment"], made["device_tokens"]
        assert deployment["state"] == "created"
        assert deployment["parameters"] == {"cutoff": 4, "label": "Test", "privacy": "public"}
        assert deployment["package"].startswith("lib:user:deployer/twins/rig@sha256:")
        assert deployment["resources"] == {
            "twin": name, "devices": ["rig"], "processors": ["smooth", "sum"],
            "connectors": [], "services": [],
        }  # fmt: skip
        assert list(tokens) == ["rig"]
        assert c.get(f"/api/v1/twins/{name}").json()["name"] == f"Test {name}"
        roles = c.get(f"/api/v1/twins/{name}/roles").json()
        assert any(r["username"] == "deployer" and r["role"] == "owner" for r in roles["roles"])
        assert {p["state"] for p in processors(c, name).values()} == {"stopped"}

        r = c.post(f"/api/v1/deployments/{name}/start")
        assert r.status_code == 200 and r.json()["state"] == "running", r.text
        sum_pid = wait_for(server, name, "sum", lambda p: p["state"] == "running")["pid"]
        wait_for(server, name, "smooth", lambda p: p["state"] == "running")
        post(server, tokens["rig"], 1, [{"x": 1.0}])  # the device token works

        # A dry run of a change shows the diff and changes nothing.
        r = c.patch(f"/api/v1/deployments/{name}", params={"dry_run": "true"},
                    json={"parameters": {"cutoff": 2}})  # fmt: skip
        assert r.status_code == 200, r.text
        plan = r.json()["plan"]
        assert plan["update"] == [
            {"type": "processor", "name": "smooth",
             "changes": [{"path": "params.cutoff_hz", "from": 4, "to": 2}]},
        ]  # fmt: skip
        assert {(e["type"], e["name"]) for e in plan["keep"]} == {
            ("twin", name), ("device", "rig"), ("processor", "sum"),
        }  # fmt: skip
        assert plan["create"] == plan["delete"] == []
        assert processors(c, name)["smooth"]["params"]["cutoff_hz"] == 4

        r = c.patch(f"/api/v1/deployments/{name}", json={"parameters": {"cutoff": 2}})
        assert r.status_code == 200, r.text
        assert r.json()["deployment"]["parameters"]["label"] == "Test"  # kept
        assert r.json()["device_tokens"] == {}
        now = processors(c, name)
        assert now["smooth"]["params"]["cutoff_hz"] == 2
        assert now["sum"]["pid"] == sum_pid  # unchanged: the same worker runs on
        wait_for(server, name, "smooth", lambda p: p["state"] == "running")

        r = c.post(f"/api/v1/deployments/{name}/stop")
        assert r.status_code == 200 and r.json()["state"] == "stopped", r.text
        assert {p["enabled"] for p in processors(c, name).values()} == {False}

        r = c.post(f"/api/v1/deployments/{name}/terminate", json={"purge": False})
        assert r.status_code == 200, r.text
        assert r.json()["state"] == "terminated"
        assert r.json()["resources"]["devices"] == r.json()["resources"]["processors"] == []
        assert processors(c, name) == {}
        assert c.get(f"/api/v1/twins/{name}/devices").json()["devices"] == []
        assert c.get(f"/api/v1/twins/{name}").status_code == 200  # the twin stays
    with server.client(tokens["rig"]) as dev:  # its token went with its device
        r = dev.post("/api/v1/device/samples", json={"seq": 2, "samples": [
            {"time": T0, "values": {"x": 1.0}}]})  # fmt: skip
        assert r.status_code == 401, r.text


def test_terminate_with_purge_removes_the_twin(server: Server, user: str) -> None:
    name = unique("purge")
    with server.client(user) as c:
        deploy(c, name, start=True)
        wait_for(server, name, "smooth", lambda p: p["state"] == "running")
        r = c.post(f"/api/v1/deployments/{name}/terminate", json={"purge": True})
        assert r.status_code == 200 and r.json()["resources"]["twin"] is None, r.text
        assert_problem(c.get(f"/api/v1/twins/{name}"), 404)
        assert c.get(f"/api/v1/deployments/{name}").json()["state"] == "terminated"
        deploy(c, name)  # the name is free again


def test_an_apply_that_fails_half_way_leaves_nothing(server: Server, user: str) -> None:
    name = unique("half")
    # Connectors are for admins: the connector service refuses it once the twin, the device
    # and the processors are made.
    broken = TWIN_YAML + "connectors:\n  - {name: plc, kind: udp, device: rig}\n"
    with server.client(user) as c:
        push(c, "broken", {"twin.yaml": broken})
        r = c.post("/api/v1/deployments", json={"package": "broken", "name": name})
        assert_problem(r, 403)
        failed = c.get(f"/api/v1/deployments/{name}").json()
        assert failed["state"] == "failed", failed
        assert failed["error"].startswith("making connector 'plc' failed:"), failed
        assert failed["resources"]["processors"] == []
        assert_problem(c.get(f"/api/v1/twins/{name}"), 404)  # devices, processors with it
    with server.admin as admin:
        assert admin.get("/api/v1/search", params={"q": name}).json()["hits"] == []
    with server.client(user) as c:
        r = c.post("/api/v1/deployments", json={"package": "rig", "name": name})
        assert r.status_code == 201, r.text  # a failed deployment holds no name


def test_two_deployments_of_one_package_side_by_side(server: Server, user: str) -> None:
    a, b = unique("side"), unique("side")
    with server.client(user) as c:
        deploy(c, a, parameters={"cutoff": 1}, start=True)
        deploy(c, b, parameters={"cutoff": 3}, start=True)
        pa = wait_for(server, a, "smooth", lambda p: p["state"] == "running")
        pb = wait_for(server, b, "smooth", lambda p: p["state"] == "running")
        assert (pa["params"]["cutoff_hz"], pb["params"]["cutoff_hz"]) == (1, 3)
        assert pa["pid"] != pb["pid"]
        listed = [d["name"] for d in c.get("/api/v1/deployments").json()["deployments"]]
        assert {a, b} <= set(listed)
        r = c.post("/api/v1/deployments", json={"package": "rig", "name": a})
        assert "exists already" in assert_problem(r, 409)["detail"]


def test_bad_requests_are_named(server: Server, user: str) -> None:
    with server.client(user) as c:
        body = {"package": "rig", "name": unique("p"), "parameters": {"cutoff": -1}}
        r = c.post("/api/v1/deployments", json=body)
        assert "parameter cutoff" in assert_problem(r, 422)["detail"]
        r = c.post("/api/v1/deployments", json={**body, "parameters": {"cutof": 1}})
        assert "'cutof' was unexpected" in assert_problem(r, 422)["detail"]
        r = c.post("/api/v1/deployments", json={"package": "rig", "name": "Not A Slug"})
        assert "slug" in assert_problem(r, 422)["detail"]
        push(c, "typo", {"twin.yaml": "descripton: x\n"})
        r = c.post("/api/v1/deployments", json={"package": "typo", "name": unique("p")})
        problem = assert_problem(r, 422)
        assert problem["errors"][0]["path"] == "descripton" and problem["errors"][0]["line"] == 1
        push(c, "unknown-var", {"twin.yaml": TWIN_YAML.replace("params.cutoff", "params.cut")})
        r = c.post("/api/v1/deployments", json={"package": "unknown-var", "name": unique("p")})
        problem = assert_problem(r, 422)
        assert problem["errors"][0]["path"] == "processors[0].params.cutoff_hz"
        assert "${params.cut}" in problem["errors"][0]["message"]
        r = c.post("/api/v1/deployments", json={"package": "nothing-here", "name": unique("p")})
        assert_problem(r, 404)
        # what a processor's service would refuse for its settings is refused in the plan
        bad = TWIN_YAML + "  - {name: bad, blueprint: lowpass, source: telemetry, params: {}}\n"
        push(c, "bad-processor", {"twin.yaml": bad})
        body = {"package": "bad-processor", "name": unique("p")}
        r = c.post("/api/v1/deployments", params={"dry_run": "true"}, json=body)
        assert assert_problem(r, 422)["detail"].startswith("processor 'bad': params")
        assert c.post("/api/v1/deployments", json=body).status_code == 422
        assert_problem(c.get(f"/api/v1/deployments/{body['name']}"), 404)  # nothing stored


def test_others_see_a_deployment_only_with_its_twin(server: Server, user: str) -> None:
    name, public = unique("mine"), unique("public")
    other = make_user(server, unique("other"))
    with server.client(user) as c:
        deploy(c, name, parameters={"privacy": "private"})
        deploy(c, public)
    with server.client(other) as o:
        assert o.get(f"/api/v1/deployments/{public}").json()["name"] == public
        r = o.post(f"/api/v1/deployments/{public}/stop")
        assert "owner role" in assert_problem(r, 403)["detail"]
        assert_problem(o.get(f"/api/v1/deployments/{name}"), 404)
        assert name not in [d["name"] for d in o.get("/api/v1/deployments").json()["deployments"]]
        assert_problem(o.post(f"/api/v1/deployments/{name}/terminate"), 404)
        # the package is in the deployer's own space: others may not read it
        r = o.post("/api/v1/deployments",
                   json={"package": "user:deployer/twins/rig", "name": unique("x")})  # fmt: skip
        assert r.status_code in (403, 404), r.text
    with server.admin as admin:
        assert admin.get(f"/api/v1/deployments/{name}").json()["state"] == "created"


def test_a_changed_document_updates_the_twin_in_place(server: Server, user: str) -> None:
    name = unique("doc")
    with server.client(user) as c:
        deploy(c, name, parameters={"label": "Old"})
        r = c.patch(f"/api/v1/deployments/{name}", json={"parameters": {"label": "New"}})
        assert r.status_code == 200, r.text
        assert r.json()["plan"]["update"] == [
            {"type": "twin", "name": name,
             "changes": [{"path": "name", "from": f"Old {name}", "to": f"New {name}"}]},
        ]  # fmt: skip
        twin = c.get(f"/api/v1/twins/{name}").json()
        assert twin["name"] == f"New {name}"
        assert [d["name"] for d in c.get(f"/api/v1/twins/{name}/devices").json()["devices"]] == [
            "rig"
        ]


SECRET_YAML = """\
parameters:
  type: object
  properties:
    password: {type: string, writeOnly: true}
    user: {type: string, default: admin}
  required: [password]
document: {version: "1.0", name: "${deployment.name}"}
services:
  - name: api
    base_url: http://127.0.0.1:9/
    auth: {method: basic, username: "${params.user}", password: "${params.password}"}
  - name: notes
    base_url: "http://127.0.0.1:9/pw-${params.password}/"
"""


def test_secret_parameters_are_sealed_and_never_shown(server: Server, user: str) -> None:
    name = unique("secret")
    with server.client(user) as c:
        push(c, "secret", {"twin.yaml": SECRET_YAML})
        body = {"package": "secret", "name": name, "parameters": {"password": "hunter2"}}
        r = c.post("/api/v1/deployments", params={"dry_run": "true"}, json=body)
        assert r.status_code == 200 and "hunter2" not in r.text, r.text
        r = c.post("/api/v1/deployments", json=body)
        assert r.status_code == 201 and "hunter2" not in r.text, r.text
        assert r.json()["deployment"]["parameters"] == {"password": "***", "user": "admin"}
        assert "hunter2" not in c.get(f"/api/v1/deployments/{name}").text
        # sent back as shown, a secret is kept; changed, the services that use it change
        r = c.patch(f"/api/v1/deployments/{name}", json={"parameters": {"password": "***"}})
        assert r.status_code == 200 and r.json()["plan"]["update"] == [], r.text
        r = c.patch(f"/api/v1/deployments/{name}", json={"parameters": {"password": "swordfish"}})
        assert r.status_code == 200, r.text
        assert {e["name"] for e in r.json()["plan"]["update"]} == {"api", "notes"}
        assert "swordfish" not in r.text and "hunter2" not in r.text
        notes = c.get(f"/api/v1/twins/{name}/services/notes").json()
        assert "pw-swordfish" in str(notes)  # the service itself has the value it was given
    file = server.data_dir / "twinlink.sqlite3"
    if file.exists():  # the store is SQLite (not PostgreSQL): the record holds neither
        with contextlib.closing(sqlite3.connect(file)) as db:
            rows = db.execute("SELECT * FROM deployments WHERE name = ?", (name,)).fetchall()
        assert rows and "swordfish" not in repr(rows) and "hunter2" not in repr(rows)
