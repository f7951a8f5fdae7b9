"""The web app's Workspace link in a real browser (Debian's chromium driven by playwright-core,
ui/e2e/workspace.mjs) against a real server: it starts the user's JupyterLab and opens it in a
new tab through the one-time link, cut off from the app's tab (no window.opener)."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from tests.conftest import ROOT, Server

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"


def test_the_workspace_link_opens_jupyterlab_in_a_new_tab(server: Server) -> None:
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
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/workspace.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=400
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == 2, run.stdout
    with server.admin as admin:
        r = admin.get("/api/v1/workspaces/me")
        assert r.status_code == 200, r.text
        assert r.json()["state"] == "running"
