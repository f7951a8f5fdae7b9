"""The web app's Co-simulations pages in a real browser (Debian's chromium driven by
playwright-core, ui/e2e/cosim.mjs) against a real server: a zip of a Maestro multi-model beside
the two mass-spring-damper FMUs uploaded to make a co-simulation writing into a twin's history,
run in batch to its end; its
connection graph (the pair's cycle, no algebraic loop), its results charted and its CSV
downloaded; run again in real time, its progress and chart moving while it runs, then stopped;
a file that is no multi-model refused with the server's reason; one made without starting it,
then deleted. Screenshots go to ui/e2e/screenshots/."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from tests.conftest import ROOT, FmuFiles, Server
from tests.integration._util import slug_of, twin_doc

pytestmark = pytest.mark.integration
UI = ROOT / "ui"
SHOTS = UI / "e2e" / "screenshots"
STEPS = 9  # the steps cosim.mjs prints "ok <name>" for

# The INTO-CPS example's pair on tests/fmus/msd_mass and msd_spring: 30 s at 0.01 s, long
# enough that a run paced to the wall clock is still going when the browser stops it.
MULTI_MODEL = {
    "fmus": {"{msd1}": "msd_mass.fmu", "{msd2}": "msd_spring.fmu"},
    "connections": {
        "{msd1}.m1.x1": ["{msd2}.m2.x1"],
        "{msd1}.m1.v1": ["{msd2}.m2.v1"],
        "{msd2}.m2.fk": ["{msd1}.m1.fk"],
    },
    "parameters": {"{msd1}.m1.x1": 1.0, "{msd2}.m2.c2": 3.0, "{msd2}.m2.cc": 2.0},
    "logVariables": {"{msd2}.m2": ["x2", "v2"]},
    "algorithm": {"type": "fixed-step", "size": 0.01},
    "startTime": 0.0,
    "endTime": 30.0,
}


def _zip(path: Path, fmu_files: FmuFiles) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("mm.json", json.dumps(MULTI_MODEL, indent=2))
        archive.write(fmu_files("msd_mass"), "msd_mass.fmu")
        archive.write(fmu_files("msd_spring"), "msd_spring.fmu")
    return path


def test_run_a_cosimulation_from_the_browser(
    server: Server, fmu_files: FmuFiles, tmp_path: Path
) -> None:
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "playwright-core").is_dir(), "run make test (npm install)"
    assert os.path.exists("/usr/bin/chromium"), "make test installs Debian's chromium"
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=twin_doc("urn:test:ui-rig", name="UI rig").encode(),
                       headers={"Content-Type": "application/yaml"})  # fmt: skip
        assert r.status_code == 200, r.text
        twin = slug_of(r)
    bad = tmp_path / "broken.json"
    bad.write_text('{"fmus": {"{a}": "a.fmu"},\n "connections": [\n')
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "E2E_URL": server.url,
        "E2E_USER": "admin",
        "E2E_PASSWORD": server.admin_password,
        "E2E_ZIP": str(_zip(tmp_path / "msd.zip", fmu_files)),
        "E2E_BAD": str(bad),
        "E2E_TWIN": twin,
        "E2E_SHOTS": str(SHOTS),
    }
    run = subprocess.run(
        [node, "e2e/cosim.mjs"], cwd=UI, env=env, capture_output=True, text=True, timeout=400
    )
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\n{server.log()[-3000:]}"
    assert run.stdout.count("ok ") == STEPS, run.stdout
    # What the browser did, as the API sees it: one co-simulation left, run again in real time
    # and stopped part way; the refused file made nothing, the other one was deleted.
    with server.admin as admin:
        r = admin.get("/api/v1/cosims")
        assert r.status_code == 200, r.text
        body = r.json()
        cosims = body["cosims"] if isinstance(body, dict) else body
        assert [c["name"] for c in cosims] == ["msd-ui"]
        cosim = cosims[0]
        assert (cosim["state"], cosim["mode"], cosim["factor"]) == ("stopped", "realtime", 1.0)
        assert 0 < cosim["progress"] < 1
        assert [i["name"] for i in cosim["system"]["instances"]] == ["msd1.m1", "msd2.m2"]
        r = admin.get(f"/api/v1/cosims/{cosim['id']}/results.csv")
        assert r.status_code == 200, r.text
        rows = r.text.strip().splitlines()
        assert 1 < len(rows) < 3002  # the stopped run's rows so far, its header first
        # The batch run chosen to write into the twin did: its columns are the twin's signals.
        assert (cosim["twin"], cosim["prefix"]) == (twin, "sim.")
        streams = admin.get(f"/api/v1/twins/{twin}/streams")
        assert streams.status_code == 200, streams.text
        assert "sim.msd2.m2.x2" in streams.text and "sim.msd2.m2.v2" in streams.text
