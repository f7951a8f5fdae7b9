"""Helpers of the lifecycle runs' tests: a twin package of scripts pushed to the library,
deployed, and its runs started, waited for and released."""

from __future__ import annotations

import io
import tarfile
from pathlib import Path
from typing import Any

import httpx

from tests.conftest import Server
from tests.integration._util import poll_until, unique

# Scripts wait for a file `go-<run id>` in their working folder (the deployment's, shared by
# its runs): a test says when each may go on, so nothing is timed. They lack the executable
# bit, as DTaaS scripts often do (run with sh).
WAIT_FOR_GO = 'while [ ! -e "go-$TWINLINK_RUN_ID" ]; do sleep 0.05; done\n'


def tar_of(files: dict[str, str]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for path, text in files.items():
            data = text.encode()
            info = tarfile.TarInfo(path)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def twin_yaml(lifecycle: str = "", runner_tags: str = "") -> str:
    return (
        "description: a package of lifecycle scripts\n"
        "parameters:\n"
        "  type: object\n"
        "  properties:\n"
        "    zeta: {type: number, default: 0.7}\n"
        "    label-text: {type: string, default: the rig}\n"
        "document: {version: '1.0', privacy: public, name: '${deployment.name}'}\n"
        "devices:\n"
        "  - {name: tingen-SAP, description: the rig}\n" + lifecycle + runner_tags
    )


def deploy_package(server: Server, scripts: dict[str, str], **yaml: str) -> str:
    """Push a package with `scripts` (phase -> text) as the admin and deploy it; its name."""
    name = unique("runs")
    files = {"twin.yaml": twin_yaml(**yaml)}
    files.update({f"lifecycle/{phase}": text for phase, text in scripts.items()})
    with server.admin as c:
        r = c.post(
            f"/api/v1/library/me/twins/{name}/versions",
            params={"format": "tar", "tag": "latest"},
            content=tar_of(files),
        )
        assert r.status_code in (200, 201), r.text
        r = c.post("/api/v1/deployments", json={"package": f"{name}@latest", "name": name})
        assert r.status_code == 201, r.text
    return name


def start_run(c: httpx.Client, name: str, phase: str) -> dict[str, Any]:
    r = c.post(f"/api/v1/deployments/{name}/runs", json={"phase": phase})
    assert r.status_code == 202, r.text
    assert r.json()["state"] == "queued"
    return r.json()  # type: ignore[no-any-return]


def run_of(c: httpx.Client, run_id: int) -> dict[str, Any]:
    r = c.get(f"/api/v1/runs/{run_id}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def wait_state(server: Server, run_id: int, *states: str, timeout_s: float = 30) -> dict[str, Any]:
    with server.admin as c:
        return poll_until(  # type: ignore[no-any-return]
            lambda: (run := run_of(c, run_id))["state"] in states and run,
            f"run {run_id} to be {' or '.join(states)}",
            timeout_s,
        )


def log_of(c: httpx.Client, run_id: int, offset: int = 0) -> str:
    r = c.get(f"/api/v1/runs/{run_id}/log", params={"offset": offset})
    assert r.status_code == 200, r.text
    return r.text


def work_dir(server: Server, run_id: int) -> Path:
    """The working folder of the run's deployment (its runs share it)."""
    with server.admin as c:
        name = run_of(c, run_id)["deployment"]
        r = c.get(f"/api/v1/deployments/{name}")
        assert r.status_code == 200, r.text
    return folder_of(server, r.json()["id"])


def folder_of(server: Server, deployment_id: int) -> Path:
    return Path(server.data_dir) / "deployments" / str(deployment_id) / "work"


def release(server: Server, run_id: int) -> None:
    """Let a run waiting in WAIT_FOR_GO go on (once it is running)."""
    wait_state(server, run_id, "running")
    (work_dir(server, run_id) / f"go-{run_id}").touch()


def wait_log(server: Server, run_id: int, text: str) -> str:
    with server.admin as c:
        return poll_until(  # type: ignore[no-any-return]
            lambda: text in (found := log_of(c, run_id)) and found, f"{text!r} in the log"
        )
