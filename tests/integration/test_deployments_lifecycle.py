"""Deployments across package versions and restarts: a new package version keeps the
parameters and changes only what changed, the versions in use are held, and a create that a
crash cut off is undone when the server starts again."""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._processors import wait_for
from tests.integration._util import assert_problem, make_user, unique
from tests.integration.test_deployments import TWIN_YAML, deploy, processors, push

pytestmark = pytest.mark.integration

# Version 1.1.0: `sum` adds 2 instead of 1, and a processor `peak` is new.
TWIN_YAML_11 = TWIN_YAML.replace('"x + 1"', '"x + 2"') + (
    "  - name: peak\n    blueprint: expression\n    source: telemetry\n"
    '    params: {outputs: {p: "x * ${params.cutoff}"}}\n'
)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def test_a_new_package_version_keeps_parameters_and_holds_versions(server: Server) -> None:
    token = make_user(server, unique("versions"))
    name = unique("ver")
    with server.client(token) as c:
        v1 = push(c, "rig", {"twin.yaml": TWIN_YAML}, "1.0.0")
        deploy(c, name, parameters={"cutoff": 3}, start=True)
        smooth_pid = wait_for(server, name, "smooth", lambda p: p["state"] == "running")["pid"]
        # the version deployed is held: it cannot be deleted while the deployment uses it
        r = c.delete(f"/api/v1/library/me/twins/rig/versions/{v1}")
        assert "deployment:" in assert_problem(r, 409)["detail"]

        v2 = push(c, "rig", {"twin.yaml": TWIN_YAML_11}, "1.1.0")
        r = c.patch(f"/api/v1/deployments/{name}", json={"package": "rig@1.1.0"})
        assert r.status_code == 200, r.text
        body = r.json()
        assert body["deployment"]["parameters"]["cutoff"] == 3  # kept
        assert v2 in body["deployment"]["package"]
        assert [(e["name"], e["changes"]) for e in body["plan"]["update"]] == [
            ("sum", [{"path": "params.outputs.s", "from": "x + 1", "to": "x + 2"}]),
        ]
        assert [e["name"] for e in body["plan"]["create"]] == ["peak"]
        now = processors(c, name)
        assert now["sum"]["params"]["outputs"] == {"s": "x + 2"}
        assert now["peak"]["params"]["outputs"] == {"p": "x * 3"}
        assert now["peak"]["enabled"] is True  # made running, as the deployment is
        assert now["smooth"]["pid"] == smooth_pid  # unchanged, untouched
        # 1.0.0 is no longer in use; 1.1.0 is
        assert c.delete(f"/api/v1/library/me/twins/rig/versions/{v1}").status_code == 204
        assert_problem(c.delete(f"/api/v1/library/me/twins/rig/versions/{v2}"), 409)
        r = c.post(f"/api/v1/deployments/{name}/terminate")
        assert r.status_code == 200, r.text
        assert c.delete(f"/api/v1/library/me/twins/rig/versions/{v2}").status_code == 204


def test_a_create_cut_off_by_a_crash_is_undone_at_start(tmp_path: Path) -> None:
    server = start_server(tmp_path / "data")
    try:
        token = make_user(server, "crash")
        name = unique("cut")
        with server.client(token) as c:
            push(c, "rig", {"twin.yaml": TWIN_YAML}, "1.0.0")
            device_token = deploy(c, name)["device_tokens"]["rig"]
    finally:
        stop_server(server)
    # As a crash in the middle of the apply leaves it: the record `applying`, with the
    # journal of what was made so far.
    with sqlite3.connect(server.data_dir / "twinlink.sqlite3") as db:
        db.execute("UPDATE deployments SET state = 'applying' WHERE name = ?", (name,))
    db.close()
    server = restart_server(server)
    try:
        with server.client(token) as c:
            d = c.get(f"/api/v1/deployments/{name}").json()
            assert d["state"] == "failed" and "server stopped" in d["error"], d
            assert d["resources"]["twin"] is None and d["resources"]["processors"] == []
            assert_problem(c.get(f"/api/v1/twins/{name}"), 404)
            assert c.get("/api/v1/twins").json()["items"] == []
        with server.client(device_token) as dev:
            r = dev.post("/api/v1/device/samples", json={"seq": 1, "samples": []})
            assert r.status_code == 401, r.text
    finally:
        stop_server(server)
