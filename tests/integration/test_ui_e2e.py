"""The web app end to end: Debian's chromium, driven by playwright-core (ui/e2e/smoke.mjs),
against a real server loaded as `make demo` loads it: the example twins, the simulated Tingen
rig streaming through `twinlink simulate tingen`, and the Tingen FMU uploaded (the browser
creates its processor), and a twin whose one signal sent one sample a while ago (a signal sent
on change: the charts must hold it to now). Screenshots go to ui/e2e/screenshots/."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator

import pytest

from tests.conftest import ROOT, FmuFiles, Server
from tests.integration._gateway import add_service, new_twin
from tests.integration._util import apply_examples

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"
STEPS = 11  # the steps smoke.mjs prints "ok <name>" for
HELD_AGO_S = 120  # how long before the test the held signal sent its only sample


@pytest.fixture
def rig(server: Server, fmu_files: FmuFiles) -> Iterator[None]:
    """The demo's data: every example twin, the Tingen FMU uploaded, the simulated rig."""
    apply_examples(server)
    with server.admin as admin:
        r = admin.put(
            "/api/v1/twins/tingen/fmus/Tingen.fmu",
            content=fmu_files("tingen").read_bytes(),
            headers={"Content-Type": "application/octet-stream"},
        )
        assert r.status_code == 201, r.text
    env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token}
    proc = subprocess.Popen(
        [sys.executable, "-m", "twinlink", "simulate", "tingen", "--rate", "100"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        yield
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
        proc.communicate(timeout=30)


def test_the_web_app_in_a_real_browser(server: Server, rig: None) -> None:
    if not (UI / "package.json").exists():
        pytest.skip("no ui/ in this tree")
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    slug = new_twin(server, interface={"signals": [{"name": "level", "unit": "m"}]})
    with server.admin as admin:
        add_service(admin, slug, "self", f"{server.url}/")  # the platform's own /healthz
        r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "tank"})
        assert r.status_code == 201, r.text
        device_token = r.json()["token"]
    # One sample, long before the live window: nothing more comes while the level holds.
    with server.client(device_token) as device:
        sample = {"time": time.time_ns() - HELD_AGO_S * 10**9, "values": {"level": 2.5}}
        r = device.post("/api/v1/device/samples", json={"seq": 1, "samples": [sample]})
        assert r.status_code == 200, r.text
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "E2E_URL": server.url,
        "E2E_USER": "admin",
        "E2E_PASSWORD": server.admin_password,
        "E2E_TOKEN": server.admin_token,
        "E2E_TWIN": slug,
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/smoke.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == STEPS, run.stdout


def test_the_api_viewer_lists_operations_and_tries_them_with_a_token(server: Server) -> None:
    """/docs in chromium (ui/e2e/apidocs.mjs): it asks for a token, then Swagger UI 5 reads
    the OpenAPI 3.1 description and lists the operations, and "Try it out" sends the token
    (GET /api/v1/auth/me answers 200 with the admin; a missing twin 404). Swagger UI 4, which
    served /docs before, showed "Unable to render this definition" instead."""
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    with server.client() as c:
        assert c.get("/docs/assets/swagger-ui-bundle.js").status_code == 200, "run make setup"
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "E2E_URL": server.url, "E2E_TOKEN": server.admin_token,
           "E2E_SHOTS": str(SHOTS)}  # fmt: skip
    run = subprocess.run(
        [node, "e2e/apidocs.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == 5, run.stdout
