"""Workspaces that stop without being asked: idle ones, and a JupyterLab that dies (shown
failed with its last log lines, started again on request); with the library in the folder."""

from __future__ import annotations

import io
import stat
import tarfile
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import assert_problem, make_user, poll_until
from tests.integration._workspaces import COOKIE, lab_processes, open_link, start

pytestmark = pytest.mark.integration
IDLE_S = 3


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"), {"TWINLINK_WORKSPACE_IDLE_S": str(IDLE_S)})
    try:
        yield srv
    finally:
        stop_server(srv)


def state(server: Server, token: str) -> dict[str, object]:
    with server.client(token) as c:
        body: dict[str, object] = c.get("/api/v1/workspaces/me").json()
    return body


def test_an_idle_workspace_stops_and_its_token_is_revoked(server: Server) -> None:
    token = make_user(server, "idler")
    start(server, token)
    processes = lab_processes(server, "idler")
    assert len(processes) == 1
    poll_until(lambda: state(server, token)["state"] == "stopped", "the idle stop", 60)
    assert not processes[0].is_running()
    with server.admin as c:
        tokens = c.get("/api/v1/tokens", params={"all": "true"}).json()["tokens"]
    mine = [t for t in tokens if t["username"] == "idler" and t["name"].startswith("workspace")]
    assert mine and all(t["state"] == "revoked" for t in mine)


def test_a_used_workspace_does_not_stop(server: Server) -> None:
    token = make_user(server, "busy")
    body = start(server, token)
    session, _ = open_link(server, body["url"])
    end = time.monotonic() + 2 * IDLE_S
    with server.client() as c:
        while time.monotonic() < end:  # used through the proxy for twice the idle time
            r = c.get("/workspaces/busy/api/status", headers={"Cookie": f"{COOKIE}={session}"})
            assert r.status_code == 200, r.text
            time.sleep(0.5)  # the pace of a user's requests, not a wait for anything
    assert state(server, token)["state"] == "running"


def test_a_crashed_workspace_is_failed_with_its_log_and_starts_again(server: Server) -> None:
    token = make_user(server, "crashy")
    start(server, token)
    [process] = lab_processes(server, "crashy")
    process.kill()
    failed = poll_until(
        lambda: (s := state(server, token))["state"] == "failed" and s, "the failed state"
    )
    assert "ended with code" in str(failed["error"])
    assert isinstance(failed["log"], list) and failed["log"]
    assert start(server, token)["state"] == "running"
    assert len(lab_processes(server, "crashy")) == 1


def test_the_folder_holds_the_users_library_and_a_read_only_common(server: Server) -> None:
    token = make_user(server, "libby")
    with server.client(token) as c:
        r = c.post("/api/v1/library/me/data/notes/versions",
                   params={"format": "tar"}, content=_tar({"a.txt": b"mine"}))  # fmt: skip
        assert r.status_code == 201, r.text
    with server.admin as c:
        r = c.post("/api/v1/library/common/tools/sim/versions",
                   params={"format": "tar"}, content=_tar({"bin/run.sh": b"echo hi"}))  # fmt: skip
        assert r.status_code == 201, r.text
    start(server, token)
    folder = server.data_dir / "workspaces" / "libby"
    own = folder / "library" / "data" / "notes" / "a.txt"
    assert own.read_bytes() == b"mine"
    assert own.stat().st_mode & stat.S_IWUSR  # a copy the user may change
    common = folder / "library" / "common" / "tools" / "sim" / "bin" / "run.sh"
    assert common.read_bytes() == b"echo hi"
    assert stat.S_IMODE(common.stat().st_mode) == 0o444
    assert stat.S_IMODE(common.parent.stat().st_mode) == 0o555
    assert "twinlink.client" in (folder / "README.md").read_text()
    own.write_bytes(b"changed")  # the user's change survives a new start
    with server.client(token) as c:
        assert c.delete("/api/v1/workspaces/me").status_code == 204
    start(server, token)
    assert own.read_bytes() == b"changed"


def _tar(files: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for name, data in files.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def test_a_workspace_that_cannot_start_says_why(tmp_path: Path) -> None:
    # 40 MB of address space: Python itself starts, JupyterLab's imports do not.
    srv = start_server(tmp_path / "data", {"TWINLINK_WORKSPACE_MEMORY_MB": "40"})
    try:
        token = make_user(srv, "tiny")
        with srv.client(token) as c:
            body = assert_problem(c.post("/api/v1/workspaces/me", timeout=120), 503)
            assert "did not start" in body["detail"]
            failed = c.get("/api/v1/workspaces/me").json()
        assert failed["state"] == "failed" and "ended with code" in failed["error"]
        # Its last lines end with what stopped it (an import that could not map its library).
        assert "Error" in failed["log"][-1], failed["log"]
        assert lab_processes(srv, "tiny") == []
        with srv.admin as c:
            tokens = c.get("/api/v1/tokens", params={"all": "true"}).json()["tokens"]
        assert all(t["state"] == "revoked" for t in tokens if t["username"] == "tiny"
                   and t["name"].startswith("workspace"))  # fmt: skip
    finally:
        stop_server(srv)
