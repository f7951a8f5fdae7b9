"""The web app end to end: Debian's chromium, driven by playwright-core (ui/e2e/smoke.mjs),
against a real server with the example twins. Screenshots go to ui/e2e/screenshots/."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from tests.conftest import ROOT, Server
from tests.integration._gateway import add_service, new_twin
from tests.integration._util import apply_examples

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"


def test_sign_in_search_open_a_twin_and_try_a_service_through_the_gateway(
    server: Server,
) -> None:
    if not (UI / "package.json").exists():
        pytest.skip("no ui/ in this tree")
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    apply_examples(server)
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "self", f"{server.url}/")  # the platform's own /healthz
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "E2E_URL": server.url,
        "E2E_USER": "admin",
        "E2E_PASSWORD": server.admin_password,
        "E2E_TWIN": slug,
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/smoke.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=180
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == 4, run.stdout
