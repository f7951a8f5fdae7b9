"""The web app's Library page in a real browser (Debian's chromium driven by playwright-core,
ui/e2e/library.mjs) against a real server: upload a file and a zip archive, see them listed,
filtered by kind and found by search, list an archive's files (the executable bit kept),
download a version as a zip, delete a version, set and remove tags, compose a twin package
from an asset put in the cart (then planned through the API). Screenshots go to
ui/e2e/screenshots/."""

from __future__ import annotations

import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from tests.conftest import ROOT, Server

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"
STEPS = 8  # the steps library.mjs prints "ok <name>" for


def _zip(path: Path) -> Path:
    """A tool of three files, one of them executable."""
    with zipfile.ZipFile(path, "w") as archive:
        run = zipfile.ZipInfo("bin/run.sh")
        run.external_attr = 0o100755 << 16
        archive.writestr(run, "#!/bin/sh\necho tank\n")
        archive.writestr("docs/README.md", "# Tank tool\n")
        archive.writestr("tool.yaml", "name: tank\n")
    return path


def test_upload_an_asset_and_see_it_listed(server: Server, tmp_path: Path) -> None:
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "E2E_URL": server.url,
        "E2E_USER": "admin",
        "E2E_PASSWORD": server.admin_password,
        "E2E_ZIP": str(_zip(tmp_path / "tank-tool.zip")),
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/library.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == STEPS, run.stdout
    # What the browser did, as the API sees it: both assets, the readings' second version only,
    # tagged stable and no longer 1.1.0.
    with server.admin as admin:
        r = admin.get("/api/v1/library", params={"scope": "common"})
        assert r.status_code == 200, r.text
        assets = {a["ref"]: a for a in r.json()["assets"]}
        assert set(assets) == {
            "common/data/tank-readings", "common/tools/tank-tool", "common/twins/tank-kit",
        }  # fmt: skip
        assert set(assets["common/data/tank-readings"]["tags"]) == {"latest", "stable"}
        assert assets["common/data/tank-readings"]["versions"] == 1
        r = admin.get("/api/v1/library/common/data/tank-readings/versions/stable")
        assert r.status_code == 200, r.text
        assert [(f["path"], f["size"]) for f in r.json()["files"]] == [("readings.csv", 23)]
        r = admin.get("/api/v1/library/common/tools/tank-tool/versions/latest")
        files = {f["path"]: f["executable"] for f in r.json()["files"]}
        assert files == {"bin/run.sh": True, "docs/README.md": False, "tool.yaml": False}
        # The composed package is one a deployment can be planned from, the tool pinned in it.
        r = admin.post(
            "/api/v1/deployments",
            params={"dry_run": "true"},
            json={"package": "common/twins/tank-kit@latest", "name": "kit-a"},
        )
        assert r.status_code == 200, r.text
        create = r.json()["plan"]["create"]
        assert [(e["type"], e["name"]) for e in create] == [("twin", "kit-a")]
        assert create[0]["spec"]["description"] == "A tank with its tool"
