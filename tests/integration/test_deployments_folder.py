"""A deployment's working folder, as DTaaS keeps a digital twin's: one folder shared by all its
lifecycle runs (what `execute` wrote is there for `analyze`), its package's files replaced by a
reconfigure to another version (the scripts' files kept), and removed once `clean` has run at
terminate; and terminate's order: the `terminate` script with everything still there (the
twin, its devices, their tokens), then the resources removed, then `clean`."""

from __future__ import annotations

import io
import tarfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._runs import WAIT_FOR_GO, deploy_package, wait_log
from tests.integration._util import poll_until, unique

pytestmark = pytest.mark.integration

TWIN_YAML = """\
devices:
  - {name: rig}
lifecycle:
  default: {timeout_s: 60}
"""
# What the twin and its device look like from a script: the twin through the run's token,
# the device through its own token (GET /api/v1/device).
PROBE = """\
import json, os, urllib.error, urllib.request

def get(path, token):
    request = urllib.request.Request(os.environ["TWINLINK_URL"].rstrip("/") + path,
                                      headers={"Authorization": "Bearer " + token})
    try:
        with urllib.request.urlopen(request) as answer:
            return answer.status, json.load(answer)
    except urllib.error.HTTPError as err:
        return err.code, None

twin = "/api/v1/twins/" + os.environ["TWINLINK_TWIN"]
code, body = get(twin + "/devices", os.environ["TWINLINK_TOKEN"])
names = sorted(d["name"] for d in body["devices"]) if body else []
print("devices", code, ",".join(names) or "-")
device = os.environ.get("TWINLINK_DEVICE_TOKEN_RIG")
print("device token", get("/api/v1/device", device)[0] if device else "none")
"""
SCRIPTS = {
    "execute": 'set -e\nmkdir -p results\necho "result of run $TWINLINK_RUN_ID" >results/out.txt\n',
    "analyze": "set -e\ncat results/out.txt\ncat data.txt\nls\n",
    # Fails on purpose: a failed terminate script does not keep the resources from going.
    "terminate": 'python3 probe.py\necho "folder: $(cat results/out.txt)"\nexit 3\n',
    "clean": "set -e\npython3 probe.py\nrm -rf results\necho cleaned\n",
}


def package(version: str) -> bytes:
    files = {
        "twin.yaml": TWIN_YAML,
        "probe.py": PROBE,
        "data.txt": f"data of {version}\n",
        f"only-in-{version}.txt": "\n",
        **{f"lifecycle/{p}": s for p, s in SCRIPTS.items()},
    }
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for path, text in files.items():
            data = text.encode()
            info = tarfile.TarInfo(path)
            info.size = len(data)  # no executable bits: run with sh, as DTaaS scripts often are
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        with srv.admin as admin:
            for version in ("1.0.0", "2.0.0"):
                url = "/api/v1/library/common/twins/foldered/versions"
                r = admin.post(url, params={"format": "tar", "tag": version},
                               content=package(version))  # fmt: skip
                assert r.status_code == 201, r.text
        yield srv
    finally:
        stop_server(srv)


def deploy(c: httpx.Client, version: str) -> dict[str, Any]:
    name = unique("foldered")
    r = c.post("/api/v1/deployments", json={"package": f"foldered@{version}", "name": name})
    assert r.status_code == 201, r.text
    return r.json()["deployment"]  # type: ignore[no-any-return]


def folder_of(server: Server, deployment: dict[str, Any]) -> Path:
    return Path(server.data_dir) / "deployments" / str(deployment["id"]) / "work"


def run(c: httpx.Client, name: str, phase: str) -> tuple[dict[str, Any], str]:
    """Run `phase` to its end; the run and its log."""
    r = c.post(f"/api/v1/deployments/{name}/runs", json={"phase": phase})
    assert r.status_code == 202, r.text
    run_id = r.json()["id"]
    ended = poll_until(lambda: ended_run(c, run_id), f"the {phase} run to end")
    return ended, c.get(f"/api/v1/runs/{run_id}/log").text


def ended_run(c: httpx.Client, run_id: int) -> dict[str, Any] | None:
    found: dict[str, Any] = c.get(f"/api/v1/runs/{run_id}").json()
    return found if found["state"] in ("succeeded", "failed", "cancelled") else None


def by_phase(c: httpx.Client, name: str, phase: str) -> dict[str, Any] | None:
    """The deployment's run of `phase`, once it has ended."""
    runs = c.get(f"/api/v1/deployments/{name}/runs").json()["runs"]
    found = [r for r in runs if r["phase"] == phase]
    return ended_run(c, found[0]["id"]) if found else None


def test_the_phases_share_one_folder_and_a_new_version_replaces_only_the_packages_files(
    server: Server,
) -> None:
    with server.admin as c:
        deployment = deploy(c, "1.0.0")
        name = deployment["name"]
        executed, _ = run(c, name, "execute")
        assert executed["state"] == "succeeded", executed
        analyzed, text = run(c, name, "analyze")  # a fresh folder would have no results/
        assert analyzed["state"] == "succeeded", text
        assert f"result of run {executed['id']}\ndata of 1.0.0\n" in text
        folder = folder_of(server, deployment)
        assert (folder / "results" / "out.txt").is_file()

        r = c.patch(f"/api/v1/deployments/{name}", json={"package": "foldered@2.0.0"})
        assert r.status_code == 200, r.text
        analyzed, text = run(c, name, "analyze")
        assert analyzed["state"] == "succeeded", text
        # the script's file kept, the package's file the new version's
        assert f"result of run {executed['id']}\ndata of 2.0.0\n" in text
        listed = set(text.splitlines())
        assert "only-in-2.0.0.txt" in listed and "only-in-1.0.0.txt" not in listed
        assert not (folder / "only-in-1.0.0.txt").exists()

        r = c.post(f"/api/v1/deployments/{name}/terminate", json={"purge": False})
        assert r.status_code == 200, r.text
        clean = poll_until(lambda: by_phase(c, name, "clean"), "the clean run", 60)
        assert clean["state"] == "succeeded"
        # the twin stays (no purge), its device is gone by the time clean runs
        assert "devices 200 -\n" in c.get(f"/api/v1/runs/{clean['id']}/log").text
    poll_until(lambda: not folder.parent.exists(), "the folder removed after clean")


def test_terminate_runs_its_script_with_everything_there_then_removes_then_cleans(
    server: Server,
) -> None:
    with server.admin as c:
        deployment = deploy(c, "1.0.0")
        name = deployment["name"]
        executed, _ = run(c, name, "execute")
        r = c.post(f"/api/v1/deployments/{name}/terminate", json={"purge": True})
        assert r.status_code == 200 and r.json()["state"] == "terminated", r.text
        clean = poll_until(lambda: by_phase(c, name, "clean"), "the clean run", 60)
        terminate = by_phase(c, name, "terminate")
        assert terminate is not None and terminate["ended_ns"] <= clean["created_ns"]
        # terminate saw the twin, its device and a working device token, and the folder
        said = c.get(f"/api/v1/runs/{terminate['id']}/log").text
        assert "devices 200 rig\ndevice token 200\n" in said
        assert f"folder: result of run {executed['id']}\n" in said
        # it failed, and the resources went all the same (the twin too: purge)
        assert (terminate["state"], terminate["exit_code"]) == ("failed", 3)
        cleaned = c.get(f"/api/v1/runs/{clean['id']}/log").text
        assert clean["state"] == "succeeded", cleaned
        assert "devices 404 -\ndevice token none\n" in cleaned and "cleaned\n" in cleaned
        shown = c.get(f"/api/v1/deployments/{name}").json()
        assert shown["state"] == "terminated"
        assert shown["resources"] == {"twin": None, "devices": [], "processors": [],
                                      "connectors": [], "services": []}  # fmt: skip
        assert c.get(f"/api/v1/twins/{name}").status_code == 404
        poll_until(lambda: not folder_of(server, deployment).parent.exists(), "the folder gone")


def test_a_terminated_deployment_is_not_reconfigured(server: Server) -> None:
    with server.admin as c:
        name = deploy(c, "1.0.0")["name"]
        assert c.post(f"/api/v1/deployments/{name}/terminate").status_code == 200
        r = c.patch(f"/api/v1/deployments/{name}", json={"package": "foldered@2.0.0"})
        assert r.status_code == 409 and "terminated" in r.json()["detail"], r.text


def test_terminating_again_removes_what_a_stopped_server_left(tmp_path: Path) -> None:
    server = start_server(tmp_path / "data")
    try:
        scripts = {"terminate": f"echo stopping\n{WAIT_FOR_GO}", "clean": "echo cleaned\n"}
        name = deploy_package(server, scripts)
        with server.admin as c:
            r = c.post(f"/api/v1/deployments/{name}/terminate")
            assert r.status_code == 200, r.text
            stopping = poll_until(lambda: c.get(f"/api/v1/deployments/{name}/runs").json()
                                  ["runs"], "the terminate run")  # fmt: skip
        wait_log(server, stopping[0]["id"], "stopping\n")
        stop_server(server)  # while the terminate script runs: the device is still there
        server = restart_server(server)
        with server.admin as c:
            shown = c.get(f"/api/v1/deployments/{name}").json()
            assert shown["state"] == "terminated" and shown["resources"]["devices"] == [
                "tingen-SAP"
            ]
            r = c.post(f"/api/v1/deployments/{name}/terminate")
            assert r.status_code == 200, r.text
            assert r.json()["resources"]["devices"] == []  # removed, the scripts not run again
            runs = c.get(f"/api/v1/deployments/{name}/runs").json()["runs"]
            assert [(run["phase"], run["state"]) for run in runs] == [("terminate", "cancelled")]
            r = c.post(f"/api/v1/deployments/{name}/terminate")  # nothing left to remove
            assert r.status_code == 409, r.text
            deployment_id = shown["id"]
        assert not (Path(server.data_dir) / "deployments" / str(deployment_id)).exists()
    finally:
        stop_server(server)
