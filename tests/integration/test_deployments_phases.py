"""A deployment's lifecycle phases as runs: `create` when it is created, `execute` from start
to stop, `terminate` then `clean` when it is terminated, each with its log; the package's
versions stay held until the last script has had its files."""

from __future__ import annotations

import io
import tarfile
from collections.abc import Iterator
from typing import Any

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import assert_problem, make_user, poll_until, unique

pytestmark = pytest.mark.integration

TWIN_YAML = """\
parameters:
  type: object
  properties: {greeting: {type: string, default: hello}}
devices:
  - {name: rig}
lifecycle:
  default: {timeout_s: 60}
  execute: {timeout_s: 0}
"""
SCRIPTS = {
    "create": '#!/bin/sh\necho "create $TWINLINK_PARAM_GREETING $TWINLINK_DEPLOYMENT"\n',
    # runs until the deployment is stopped
    "execute": "#!/bin/sh\necho executing\nwhile true; do sleep 0.1; done\n",
    "terminate": "#!/bin/sh\necho terminating\n",
    "clean": "#!/bin/sh\necho cleaning\n",
}


def package() -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        files = {"twin.yaml": TWIN_YAML, **{f"lifecycle/{p}": s for p, s in SCRIPTS.items()}}
        for path, text in files.items():
            data = text.encode()
            info = tarfile.TarInfo(path)
            info.size, info.mode = len(data), 0o755 if path.startswith("lifecycle/") else 0o644
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        with srv.admin as admin:
            for name in ("scripted", "scripted-too"):
                url = f"/api/v1/library/common/twins/{name}/versions"
                r = admin.post(url, params={"format": "tar", "tag": "1.0.0"}, content=package())
                assert r.status_code == 201, r.text
        yield srv
    finally:
        stop_server(srv)


def runs(c: httpx.Client, name: str) -> dict[str, dict[str, Any]]:
    """The deployment's runs by phase (the newest of each)."""
    r = c.get(f"/api/v1/deployments/{name}/runs")
    assert r.status_code == 200, r.text
    out: dict[str, dict[str, Any]] = {}
    for run in reversed(r.json()["runs"]):  # oldest first: the newest of a phase wins
        out[run["phase"]] = run
    return out


def ended(c: httpx.Client, name: str, phase: str) -> dict[str, Any] | None:
    run = runs(c, name).get(phase)
    return run if run and run["state"] in ("succeeded", "failed", "cancelled") else None


def log_of(c: httpx.Client, run: dict[str, Any]) -> str:
    return c.get(f"/api/v1/runs/{run['id']}/log").text


def test_phases_run_through_the_lifecycle(server: Server) -> None:
    name = unique("phased")
    with server.admin as c:
        r = c.post("/api/v1/deployments", json={"package": "scripted", "name": name})
        assert r.status_code == 201, r.text
        created = poll_until(lambda: ended(c, name, "create"), "the create run")
        assert created["state"] == "succeeded", created
        assert log_of(c, created).startswith(f"create hello {name}")

        assert c.post(f"/api/v1/deployments/{name}/start").status_code == 200
        poll_until(lambda: runs(c, name).get("execute", {}).get("state") == "running",
                   "the execute run")  # fmt: skip
        assert c.post(f"/api/v1/deployments/{name}/stop").status_code == 200
        assert runs(c, name)["execute"]["state"] == "cancelled"

        r = c.post(f"/api/v1/deployments/{name}/terminate")
        assert r.status_code == 200 and r.json()["state"] == "terminated", r.text
        clean = poll_until(lambda: ended(c, name, "clean"), "the clean run", 60)
        terminate = runs(c, name)["terminate"]
        assert (terminate["state"], clean["state"]) == ("succeeded", "succeeded")
        assert terminate["ended_ns"] <= clean["created_ns"]  # one after the other
        assert "cleaning" in log_of(c, clean)
        # once the scripts are done, nothing holds the package's version any more
        poll_until(lambda: c.delete("/api/v1/library/common/twins/scripted/versions/1.0.0")
                   .status_code == 204, "the version released")  # fmt: skip


def test_who_may_not_run_scripts_may_not_deploy_a_package_that_runs_them(server: Server) -> None:
    token = make_user(server, unique("plain"))
    with server.client(token) as c:
        body = {"package": "common/twins/scripted-too", "name": unique("refused")}
        r = c.post("/api/v1/deployments", json=body)
        assert "lifecycle scripts" in assert_problem(r, 403)["detail"]
        assert c.get("/api/v1/deployments").json()["deployments"] == []
