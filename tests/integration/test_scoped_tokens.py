"""A lifecycle run's token on a real server: scoped to its deployment's twin (it reads and
writes that twin, and reads the library, with its owner's rights), refused everywhere else
(403, also for an admin's run), and revoked when its run ends."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from tests.conftest import Server, start_server, stop_server
from tests.integration._gateway import raw_request
from tests.integration._live import ws_url
from tests.integration._runs import WAIT_FOR_GO, deploy_package, release, start_run, wait_log
from tests.integration._runs import wait_state as wait_run
from tests.integration._util import apply, assert_problem, twin_doc, unique

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def _run_token(server: Server) -> tuple[str, int, str]:
    """A deployment (of the admin) whose run shows its token and waits: (twin, run, token).
    A test would never print a token; here the token is what is under test."""
    name = deploy_package(server, {"analyze": f'echo "token $TWINLINK_TOKEN"\n{WAIT_FOR_GO}'})
    with server.admin as c:
        run = start_run(c, name, "analyze")
    token = wait_log(server, run["id"], "token ").split()[1]
    return name, run["id"], token


def test_a_runs_token_reaches_its_twin_and_nothing_else(server: Server) -> None:
    twin, run_id, token = _run_token(server)
    other = unique("other")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:test:{other}", name="Other", privacy="public", slug=other))
    with server.client(token) as c:
        assert c.get(f"/api/v1/twins/{twin}").status_code == 200
        r = c.post(f"/api/v1/twins/{twin}/devices", json={"name": "probe"})
        assert r.status_code == 201, r.text  # it writes its twin
        assert c.get(f"/api/v1/twins/{twin}/devices").status_code == 200
        assert c.get("/api/v1/library").status_code == 200  # reads of the library
        # The admin's token could do all of these; the run's, scoped, none.
        for method, path, body in [
            ("GET", f"/api/v1/twins/{other}", None),
            ("POST", f"/api/v1/twins/{other}/devices", {"name": "probe"}),
            ("GET", "/api/v1/twins", None),
            ("GET", "/api/v1/users", None),
            ("POST", "/api/v1/tokens", {"name": "escape"}),
            ("GET", "/api/v1/tokens", None),
            ("GET", f"/api/v1/runs/{run_id}", None),
            ("GET", f"/api/v1/deployments/{twin}", None),
            ("POST", f"/api/v1/library/me/data/{unique('x')}/versions", None),
            ("GET", f"/api/v1/twins/{twin}x", None),
        ]:
            problem = assert_problem(c.request(method, path, json=body), 403)
            assert f"scoped to twin {twin!r}" in problem["detail"], (path, problem)
        # Its twin's gateway passes the scope (no such service: 404); another twin's does not.
        assert c.get(f"/twins/{twin}/services/nothing/").status_code == 404
        r = c.get(f"/twins/{other}/services/nothing/")
        assert r.status_code == 403 and "scoped to twin" in r.text
    # A path that walks out of the twin is not the twin's, however it is spelled.
    for target in (
        f"/api/v1/twins/{twin}/../../users",
        f"/api/v1/twins/{twin}/%2e%2e/%2e%2e/users",
        f"/api/v1/twins/{twin}//../users",
    ):
        status, _ = raw_request(server, "GET", target, {"Authorization": f"Bearer {token}"})
        assert status in (403, 404), target
    release(server, run_id)
    wait_run(server, run_id, "succeeded")


def test_a_runs_token_cannot_open_the_websockets_that_name_no_twin(server: Server) -> None:
    _, run_id, token = _run_token(server)
    headers = {"Authorization": f"Bearer {token}"}
    for path in ("/api/v1/live", f"/api/v1/runs/{run_id}/log/ws"):
        with (
            connect(ws_url(server, path), additional_headers=headers, open_timeout=30) as ws,
            pytest.raises(ConnectionClosed) as closed,
        ):
            ws.recv(timeout=30)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401, path
        assert "scoped to twin" in closed.value.rcvd.reason
    release(server, run_id)
    wait_run(server, run_id, "succeeded")


def test_a_runs_token_is_revoked_when_the_run_ends(server: Server) -> None:
    twin, run_id, token = _run_token(server)
    with server.client(token) as c:
        assert c.get(f"/api/v1/twins/{twin}").status_code == 200
        release(server, run_id)
        wait_run(server, run_id, "succeeded")
        problem = assert_problem(c.get(f"/api/v1/twins/{twin}"), 401)
        assert "revoked" in problem["detail"]
    with server.admin as admin:  # listed as a run token of the deployment's owner, revoked
        tokens = admin.get("/api/v1/tokens").json()
    rows = tokens["tokens"] if isinstance(tokens, dict) else tokens
    mine = [t for t in rows if t.get("kind") == "run" and t["name"].startswith(f"run {run_id} ")]
    assert len(mine) == 1 and mine[0]["state"] == "revoked", mine
