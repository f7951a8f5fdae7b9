"""The web app's Deployments pages in a real browser (Debian's chromium driven by
playwright-core, ui/e2e/deployments.mjs) against a real server: a twin package in the library,
deployed through the form generated from its parameter schema (a value over its maximum
refused before sending), the plan shown, then deployed and running; a lifecycle phase run to
its end, another followed live then cancelled, both logs whole after a reload; reconfigured
(new parameters, the diff plan, applied); stopped; and its package's version refused deletion
(held). Screenshots go to ui/e2e/screenshots/."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import tarfile

import pytest

from tests.conftest import ROOT, Server

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"

TWIN_YAML = """\
description: A tank for the web app's test
parameters:
  type: object
  properties:
    capacity:
      {type: number, default: 2.5, minimum: 0.1, maximum: 10, description: tank volume in m³}
    sensors: {type: integer, default: 1, minimum: 1, maximum: 4}
    medium: {enum: [water, oil], default: water}
    heated: {type: boolean, default: false}
  additionalProperties: false
document:
  version: "1.0"
  name: Tank ${deployment.name}
  description: ${params.medium} tank of ${params.capacity} m³
devices:
  - {name: level, description: the level sensor}
"""
ANALYZE = """\
#!/bin/sh
echo "analyzing $TWINLINK_DEPLOYMENT"
echo "capacity $TWINLINK_PARAM_CAPACITY"
"""
# Runs until the browser cancels it (the run's process group is killed then).
EVOLVE = """\
#!/bin/sh
echo "evolving $TWINLINK_DEPLOYMENT"
exec sleep 600
"""


def _package() -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w:gz") as tar:
        files = [
            ("twin.yaml", TWIN_YAML, 0o644),
            ("lifecycle/analyze", ANALYZE, 0o755),
            ("lifecycle/evolve", EVOLVE, 0o755),
        ]
        for path, text, mode in files:
            data = text.encode()
            info = tarfile.TarInfo(path)
            info.size, info.mode = len(data), mode
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def test_deploy_a_package_through_the_form_then_stop_it(server: Server) -> None:
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    with server.admin as admin:
        r = admin.post(
            "/api/v1/library/common/twins/ui-tank/versions",
            params={"format": "tgz", "tag": ["1.0.0", "latest"]},
            content=_package(),
        )
        assert r.status_code == 201, r.text
        paths = admin.get("/openapi.json").json()["paths"]
    runs = "/api/v1/deployments/{name}/runs" in paths
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "E2E_URL": server.url,
        "E2E_USER": "admin",
        "E2E_PASSWORD": server.admin_password,
        "E2E_RUNS": "1" if runs else "0",
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/deployments.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == (10 if runs else 7), run.stdout
    # What the browser did, as the API sees it.
    with server.admin as admin:
        r = admin.get("/api/v1/deployments/tank-a")
        assert r.status_code == 200, r.text
        deployment = r.json()
        assert deployment["state"] == "stopped"
        assert deployment["parameters"] == {
            "capacity": 5, "sensors": 1, "medium": "oil", "heated": True,
        }  # fmt: skip
        assert deployment["resources"]["devices"] == ["level"]
        doc = admin.get("/api/v1/twins/tank-a").json()["document"]
        assert doc["description"] == "oil tank of 5 m³"
        if runs:
            r = admin.get("/api/v1/deployments/tank-a/runs")
            assert [(x["phase"], x["state"]) for x in r.json()["runs"]] == [
                ("evolve", "cancelled"), ("analyze", "succeeded"),
            ]  # fmt: skip
            assert r.json()["runs"][1]["exit_code"] == 0
        r = admin.get("/api/v1/library/common/twins/ui-tank/versions")
        assert len(r.json()["versions"]) == 1  # the held version was not deleted
