"""Workspaces end to end: a real server runs real JupyterLabs, reached through its proxy by
their owners alone (issue 16, section 4). The workspaces of the module's users are shared by
its tests (each takes seconds to start)."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest
from websockets.sync.client import ClientConnection, connect
from websockets.typing import Subprotocol

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import assert_problem, make_user, poll_until
from tests.integration._workspaces import COOKIE, lab_processes, open_link, run_code, start

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture(scope="module")
def users(server: Server) -> dict[str, str]:
    return {name: make_user(server, name) for name in ("alice", "bob")}


@pytest.fixture(scope="module")
def sessions(server: Server, users: dict[str, str]) -> dict[str, str]:
    """alice's and bob's workspaces started, each with its session cookie."""
    found = {}
    for name, token in users.items():
        body = start(server, token)
        assert body["url"].startswith(f"/workspaces/{name}/?ticket=")
        found[name], _ = open_link(server, body["url"])
    return found


def cookie(session: str) -> dict[str, str]:
    return {"Cookie": f"{COOKIE}={session}"}


def test_the_link_sets_a_strict_cookie_scoped_to_the_workspace(
    server: Server, users: dict[str, str], sessions: dict[str, str]
) -> None:
    body = start(server, users["alice"])  # idempotent: the same workspace, a new link
    session, r = open_link(server, body["url"])
    assert r.headers["location"] == "/workspaces/alice/"  # the ticket left out
    attributes = {a.strip().lower() for a in r.headers["set-cookie"].split(";")[1:]}
    assert {"path=/workspaces/alice/", "httponly", "samesite=strict"} <= attributes
    with server.client() as c:
        status = c.get("/workspaces/alice/api/status", headers=cookie(session))
        assert status.status_code == 200, status.text
        assert "started" in status.json()
        lab = c.get("/workspaces/alice/lab", headers=cookie(session))
        assert lab.status_code == 200 and "JupyterLab" in lab.text
        again = c.get(body["url"])  # a ticket is good once
    assert_problem(again, 403)


def test_nobody_else_reaches_a_workspace(
    server: Server, users: dict[str, str], sessions: dict[str, str]
) -> None:
    status = "/workspaces/alice/api/status"
    with server.client() as c:
        assert_problem(c.get(status), 403)  # no cookie
        assert_problem(c.get(status, headers=cookie(sessions["bob"])), 403)
        assert_problem(c.get(status, headers=cookie("made-up")), 403)
        kernels = c.post("/workspaces/alice/api/kernels", json={}, headers=cookie(sessions["bob"]))
        assert_problem(kernels, 403)
        bob_link = start(server, users["bob"])["url"]  # bob's ticket at alice's address
        assert_problem(c.get(bob_link.replace("/bob/", "/alice/")), 403)
    with server.client(users["bob"]) as c:
        assert_problem(c.get(status), 403)  # bob's platform token
        assert c.post("/api/v1/workspaces/alice").status_code == 405  # no way to start hers
        assert_problem(c.delete("/api/v1/workspaces/alice"), 403)
    with server.client(users["alice"]) as c:  # her own token works, for scripts
        assert c.get(status).status_code == 200
        assert c.get("/api/v1/workspaces/me").json()["state"] == "running"


def test_files_go_both_ways_through_the_proxy(server: Server, sessions: dict[str, str]) -> None:
    text = "twinlink\n" * 300_000  # 2.7 MB, sent in chunks of unknown total length
    body = json.dumps({"type": "file", "format": "text", "content": text}).encode()

    def chunks() -> Iterator[bytes]:
        for i in range(0, len(body), 1 << 16):
            yield body[i : i + (1 << 16)]

    url = "/workspaces/alice/api/contents/notes.txt"
    with server.client() as c:
        r = c.put(url, content=chunks(), headers=cookie(sessions["alice"]))
        assert r.status_code in (200, 201), r.text
        back = c.get(url, params={"content": "1"}, headers=cookie(sessions["alice"]))
    assert back.status_code == 200 and back.json()["content"] == text
    assert (server.data_dir / "workspaces" / "alice" / "notes.txt").read_text() == text


def test_a_change_from_another_site_is_refused(server: Server, sessions: dict[str, str]) -> None:
    headers = {**cookie(sessions["alice"]), "Origin": "http://evil.example"}
    with server.client() as c:
        assert_problem(c.post("/workspaces/alice/api/kernels", json={}, headers=headers), 403)


def test_a_kernel_runs_code_over_the_proxied_websocket(
    server: Server, users: dict[str, str], sessions: dict[str, str]
) -> None:
    headers = cookie(sessions["alice"])
    with server.client() as c:
        r = c.post("/workspaces/alice/api/kernels", json={}, headers=headers)
    assert r.status_code == 201, r.text
    ws_url = (
        server.url.replace("http://", "ws://")
        + f"/workspaces/alice/api/kernels/{r.json()['id']}/channels"
    )
    code = (
        "import os, pandas\n"
        "from twinlink.client import Client\n"
        "print(os.environ['TWINLINK_URL'])\n"
        "print(sorted(k for k in os.environ if k.startswith('TWINLINK_')))\n"
        "print(Client().me()['username'])\n"  # no arguments: the workspace's URL and token
    )
    out = run_code(ws_url, headers, code).splitlines()
    assert out == [server.url, "['TWINLINK_TOKEN', 'TWINLINK_URL']", "alice"]
    with pytest.raises(Exception, match="403"):  # another site's page cannot open one
        run_code(ws_url, {**headers, "Origin": "http://evil.example"}, "print(1)")


def test_a_terminal_and_the_kernel_protocol_pass_the_proxy(
    server: Server, sessions: dict[str, str]
) -> None:
    headers = cookie(sessions["alice"])
    base = server.url.replace("http://", "ws://") + "/workspaces/alice"
    with server.client() as c:
        name = c.post("/workspaces/alice/api/terminals", headers=headers).json()["name"]
        kernel = c.post("/workspaces/alice/api/kernels", json={}, headers=headers).json()["id"]
    with connect(f"{base}/terminals/websocket/{name}", additional_headers=headers) as ws:
        ws.send(json.dumps(["stdin", "echo ws-$TWINLINK_URL-ok\r"]))
        printed: list[str] = []
        poll_until(lambda: f"ws-{server.url}-ok" in _stdout(ws, printed), "the echo", 30)
    # JupyterLab's own client asks for the kernel protocol as a WebSocket subprotocol.
    protocol = Subprotocol("v1.kernel.websocket.jupyter.org")
    url = f"{base}/api/kernels/{kernel}/channels"
    with connect(url, additional_headers=headers, subprotocols=[protocol]) as ws:
        assert ws.subprotocol == protocol


def _stdout(ws: ClientConnection, printed: list[str]) -> str:
    """All the terminal printed so far, with its next message read (["stdout", text] or
    another kind)."""
    message = json.loads(ws.recv(timeout=30))
    if message[0] == "stdout":
        printed.append(str(message[1]))
    return "".join(printed)


def test_stop_ends_the_process_and_revokes_its_token(
    server: Server, users: dict[str, str], sessions: dict[str, str]
) -> None:
    token = run_code(_kernel(server, sessions["bob"]), cookie(sessions["bob"]),
                     "import os; print(os.environ['TWINLINK_TOKEN'])").strip()  # fmt: skip
    with server.client(token) as c:
        assert c.get("/api/v1/auth/me").json()["username"] == "bob"
    processes = lab_processes(server, "bob")
    assert len(processes) == 1
    with server.client(users["bob"]) as c:
        assert c.delete("/api/v1/workspaces/me").status_code == 204
        assert c.get("/api/v1/workspaces/me").json()["state"] == "stopped"
        assert_problem(c.get("/workspaces/bob/api/status"), 404)  # bob's token: it is not running
    with server.client() as c:  # the session ended with it
        assert_problem(c.get("/workspaces/bob/api/status", headers=cookie(sessions["bob"])), 403)
    assert not processes[0].is_running()
    with server.client(token) as c:
        assert_problem(c.get("/api/v1/auth/me"), 401)


def test_admins_see_every_workspace(server: Server, sessions: dict[str, str]) -> None:
    with server.admin as c:
        listed = c.get("/api/v1/workspaces").json()["workspaces"]
    states = {w["user"]: w["state"] for w in listed}
    assert states["alice"] == "running"
    assert all(w["url"] is None for w in listed)  # links are for their owners


def test_the_servers_stop_stops_every_workspace(server: Server) -> None:
    srv = start_server(server.data_dir.parent / "stop-data")
    token = make_user(srv, "carol")
    start(srv, token)
    processes = lab_processes(srv, "carol")
    assert len(processes) == 1
    stop_server(srv)
    poll_until(lambda: not processes[0].is_running(), "carol's JupyterLab to end")


def _kernel(server: Server, session: str) -> str:
    r = httpx.post(f"{server.url}/workspaces/bob/api/kernels", json={}, headers=cookie(session))
    assert r.status_code == 201, r.text
    return (
        server.url.replace("http://", "ws://")
        + f"/workspaces/bob/api/kernels/{r.json()['id']}/channels"
    )


def test_workspaces_turned_off(server: Server) -> None:
    srv = start_server(
        server.data_dir.parent / "off-data", {"TWINLINK_WORKSPACES_ENABLED": "false"}
    )
    try:
        token = make_user(srv, "dora")
        with srv.client(token) as c:
            body = assert_problem(c.post("/api/v1/workspaces/me"), 404)
            assert "TWINLINK_WORKSPACES_ENABLED" in body["detail"]
            assert c.get("/workspaces/dora/api/status").status_code == 404
    finally:
        stop_server(srv)
