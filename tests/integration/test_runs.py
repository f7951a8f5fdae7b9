"""Lifecycle runs on a real server with real processes: logs streamed live and kept, every
run kept and told apart, runs killed, timed out, over their memory, cancelled, the
environment they see, runner tags, and what a server's stop (or death) does to them."""

from __future__ import annotations

import json
import os
import signal
from collections.abc import Iterator
from pathlib import Path

import psutil
import pytest
from websockets.sync.client import connect

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._live import ws_url
from tests.integration._runs import (
    WAIT_FOR_GO,
    deploy_package,
    log_of,
    release,
    run_of,
    start_run,
    wait_log,
    wait_state,
    work_dir,
)
from tests.integration._util import assert_problem, make_user, poll_until

pytestmark = pytest.mark.integration

TIMEOUT_S = 30.0


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def test_a_runs_log_streams_live_and_is_kept_after_the_socket_closes(server: Server) -> None:
    name = deploy_package(
        server, {"analyze": f"echo first\n{WAIT_FOR_GO}echo second >&2\nexit 3\n"}
    )
    with server.admin as c:
        run = start_run(c, name, "analyze")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    url = ws_url(server, f"/api/v1/runs/{run['id']}/log/ws")
    with connect(url, additional_headers=headers, open_timeout=TIMEOUT_S) as ws:
        assert ws.recv(timeout=TIMEOUT_S) == b"first\n"  # while the script still runs
        with server.admin as c:
            assert run_of(c, run["id"])["state"] == "running"
        release(server, run["id"])
        frames = []
        while not isinstance(frame := ws.recv(timeout=TIMEOUT_S), str):
            frames.append(frame)
        assert json.loads(frame) == {"state": "failed", "exit_code": 3}
    assert b"".join(frames) == b"second\n[twinlink] failed: exited with code 3\n"
    with server.admin as c:
        assert log_of(c, run["id"]) == "first\nsecond\n[twinlink] failed: exited with code 3\n"
        assert log_of(c, run["id"], offset=6) == "second\n[twinlink] failed: exited with code 3\n"
        r = c.get(f"/api/v1/runs/{run['id']}/log")
        assert r.headers["x-run-state"] == "failed"
        ended = run_of(c, run["id"])
    assert ended["error"] == "exited with code 3" and ended["started_by"] == "admin"
    assert ended["created_ns"] <= ended["started_ns"] <= ended["ended_ns"]
    # The working folder is the deployment's: it stays after the run, as the log does.
    assert (work_dir(server, run["id"]) / f"go-{run['id']}").is_file()


def test_every_run_is_kept_and_concurrent_runs_of_a_phase_are_told_apart(server: Server) -> None:
    script = f'echo "I am run $TWINLINK_RUN_ID"\n{WAIT_FOR_GO}exit $((TWINLINK_RUN_ID % 5 + 1))\n'
    name = deploy_package(server, {"analyze": script})
    with server.admin as c:
        first, second = start_run(c, name, "analyze"), start_run(c, name, "analyze")
    assert first["id"] != second["id"]
    for run in (first, second):  # both running at once
        wait_log(server, run["id"], f"I am run {run['id']}\n")
    for run in (second, first):
        release(server, run["id"])
        ended = wait_state(server, run["id"], "failed")
        assert ended["exit_code"] == run["id"] % 5 + 1
    with server.admin as c:
        for run in (first, second):
            assert log_of(c, run["id"]).startswith(f"I am run {run['id']}\n")
        third = start_run(c, name, "analyze")
        release(server, third["id"])
        wait_state(server, third["id"], "failed")
        r = c.get(f"/api/v1/deployments/{name}/runs")
        assert r.status_code == 200, r.text
        assert [x["id"] for x in r.json()["runs"]] == [third["id"], second["id"], first["id"]]
        r = c.get(f"/api/v1/deployments/{name}/runs", params={"before": third["id"], "limit": 1})
        assert [x["id"] for x in r.json()["runs"]] == [second["id"]]


def test_a_run_killed_mid_phase_is_failed_with_its_log(server: Server) -> None:
    name = deploy_package(server, {"evolve": f"echo evolving\n{WAIT_FOR_GO}"})
    with server.admin as c:
        run = start_run(c, name, "evolve")
    wait_log(server, run["id"], "evolving\n")
    os.kill(_pid(server, run["id"]), signal.SIGKILL)
    ended = wait_state(server, run["id"], "failed")
    assert ended["error"] == "killed by signal SIGKILL" and ended["exit_code"] == -9
    with server.admin as c:
        assert log_of(c, run["id"]) == "evolving\n[twinlink] failed: killed by signal SIGKILL\n"


def _pid(server: Server, run_id: int) -> int:
    """The pid of the run's script: the process working in its dir."""
    work = str(work_dir(server, run_id))
    for proc in psutil.Process(server.process.pid).children(recursive=True):
        try:
            if proc.cwd() == work and proc.pid == os.getpgid(proc.pid):
                return proc.pid
        except (psutil.Error, OSError):
            continue
    raise AssertionError(f"no process of run {run_id}")


def test_a_run_over_its_timeout_is_killed_with_its_children(server: Server) -> None:
    lifecycle = "lifecycle:\n  save: {timeout_s: 1}\n"
    name = deploy_package(
        server, {"save": 'sleep 600 &\necho "child $!"\nwait\n'}, lifecycle=lifecycle
    )
    with server.admin as c:
        run = start_run(c, name, "save")
    child = int(wait_log(server, run["id"], "child ").split()[1])
    ended = wait_state(server, run["id"], "failed")
    assert ended["error"] == "timed out after 1 s" and ended["timeout_s"] == 1
    poll_until(lambda: not _alive(child), "the run's background child to be killed")


def _alive(pid: int) -> bool:
    try:
        return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def test_a_run_over_its_memory_limit_fails(server: Server) -> None:
    hog = "python3 -c 'b = bytearray(300 << 20); print(\"got it\")'\n"
    lifecycle = "lifecycle:\n  terminate: {memory_mb: 200}\n  clean: {memory_mb: 2048}\n"
    name = deploy_package(server, {"terminate": hog, "clean": hog}, lifecycle=lifecycle)
    with server.admin as c:
        over, within = start_run(c, name, "terminate"), start_run(c, name, "clean")
    ended = wait_state(server, over["id"], "failed", "succeeded")
    assert ended["state"] == "failed" and ended["memory_mb"] == 200
    with server.admin as c:
        assert "MemoryError" in log_of(c, over["id"])
    assert wait_state(server, within["id"], "failed", "succeeded")["state"] == "succeeded"


def test_a_run_sees_only_the_environment_it_is_given(server: Server) -> None:
    name = deploy_package(server, {"create": "env | sort\npwd\nls\n"})
    with server.admin as c:
        run = start_run(c, name, "create")
        assert wait_state(server, run["id"], "succeeded", "failed")["state"] == "succeeded"
        text = log_of(c, run["id"])
    lines = text.splitlines()
    env = dict(line.split("=", 1) for line in lines if "=" in line)
    work = str(work_dir(server, run["id"]))
    assert env["HOME"] == work and work in lines  # pwd
    assert {"lifecycle", "twin.yaml"} <= set(lines)  # the package's files
    assert env["TWINLINK_TWIN"] == name and env["TWINLINK_DEPLOYMENT"] == name
    assert env["TWINLINK_PHASE"] == "create" and env["TWINLINK_RUN_ID"] == str(run["id"])
    assert env["TWINLINK_URL"] == server.url
    assert json.loads(env["TWINLINK_PARAMS"]) == {"zeta": 0.7, "label-text": "the rig"}
    assert env["TWINLINK_PARAM_ZETA"] == "0.7"
    assert env["TWINLINK_PARAM_LABEL_TEXT"] == "the rig"
    assert env["TWINLINK_DEVICE_TOKEN_TINGEN_SAP"].startswith("tl")
    assert env["TWINLINK_TOKEN"].startswith("tl")
    # The server's own environment (its admin token and password, set by start_server) is
    # not there: nothing but what docs/runs.md lists.
    expected = {"PATH", "HOME", "LANG", "PWD", "SHLVL", "_", "OLDPWD"}
    extra = {k for k in env if not k.startswith("TWINLINK_")} - expected
    assert extra == set(), extra
    assert server.admin_token not in text and server.admin_password not in text
    assert not {"TWINLINK_ADMIN_TOKEN", "TWINLINK_ADMIN_PASSWORD", "TWINLINK_DATA_DIR"} & set(env)


def test_a_missing_phase_is_a_clear_404_and_bad_names_a_422(server: Server) -> None:
    name = deploy_package(server, {"create": "true\n"})
    with server.admin as c:
        problem = assert_problem(
            c.post(f"/api/v1/deployments/{name}/runs", json={"phase": "analyze"}), 404
        )
        assert "lifecycle/analyze" in problem["detail"]
        assert_problem(c.post(f"/api/v1/deployments/{name}/runs", json={"phase": "../x"}), 422)
        assert_problem(c.get("/api/v1/runs/999999"), 404)
        assert_problem(c.get("/api/v1/runs/99999999999999999999"), 422)
        assert_problem(c.get("/api/v1/runs/1/log", params={"offset": -1}), 422)


def test_a_cancelled_run_is_cancelled_and_its_process_group_gone(server: Server) -> None:
    name = deploy_package(server, {"analyze": f'sleep 600 &\necho "child $!"\n{WAIT_FOR_GO}'})
    with server.admin as c:
        run = start_run(c, name, "analyze")
        child = int(wait_log(server, run["id"], "child ").split()[1])
        r = c.post(f"/api/v1/runs/{run['id']}/cancel")
        assert r.status_code == 200, r.text
        assert r.json()["state"] == "cancelled"
        assert "[twinlink] cancelled" in log_of(c, run["id"])
        again = c.post(f"/api/v1/runs/{run['id']}/cancel")  # ended: nothing to do
        assert again.status_code == 200 and again.json()["state"] == "cancelled"
    poll_until(lambda: not _alive(child), "the cancelled run's child to be gone")


def test_only_admins_run_scripts_by_default(server: Server) -> None:
    name = deploy_package(server, {"analyze": f"{WAIT_FOR_GO}"})
    with server.admin as c:
        run = start_run(c, name, "analyze")
    token = make_user(server, f"user-{run['id']}")
    with server.client(token) as c:
        assert run_of(c, run["id"])["phase"] == "analyze"  # the twin is public: its runs too
        problem = assert_problem(
            c.post(f"/api/v1/deployments/{name}/runs", json={"phase": "analyze"}), 403
        )
        assert "script_runners" in problem["detail"]
        assert_problem(c.post(f"/api/v1/runs/{run['id']}/cancel"), 403)
    release(server, run["id"])
    wait_state(server, run["id"], "succeeded")


def test_a_run_whose_tags_no_node_has_waits_queued_until_one_has_them(tmp_path: Path) -> None:
    server = start_server(tmp_path / "data")
    try:
        tagged = deploy_package(
            server, {"execute": "echo ran on a tagged node\n"}, runner_tags="runner_tags: [gpu]\n"
        )
        plain = deploy_package(server, {"analyze": "true\n"})
        with server.admin as c:
            waiting = start_run(c, tagged, "execute")
            for _ in range(3):  # other runs come and go: it stays queued
                done = start_run(c, plain, "analyze")
                wait_state(server, done["id"], "succeeded")
            queued = run_of(c, waiting["id"])
        assert queued["state"] == "queued" and queued["node"] is None
        assert queued["runner_tags"] == ["gpu"]
        stop_server(server)
        server = restart_server(server, {"TWINLINK_RUNNER_TAGS": "lab, gpu"})
        ended = wait_state(server, waiting["id"], "succeeded")
        assert ended["node"] is not None
        with server.admin as c:
            assert log_of(c, waiting["id"]).startswith("ran on a tagged node\n")
    finally:
        stop_server(server)


def test_a_server_stop_cancels_its_runs_and_a_crash_fails_them(tmp_path: Path) -> None:
    server = start_server(tmp_path / "data")
    try:
        name = deploy_package(server, {"execute": f"echo up\n{WAIT_FOR_GO}"})
        with server.admin as c:
            stopped = start_run(c, name, "execute")
        wait_log(server, stopped["id"], "up\n")
        pgid = _pid(server, stopped["id"])
        stop_server(server)  # a clean stop: the run is cancelled, its group killed
        server = restart_server(server)
        assert not _alive(pgid)
        with server.admin as c:
            assert run_of(c, stopped["id"])["state"] == "cancelled"
            crashed = start_run(c, name, "execute")
        wait_log(server, crashed["id"], "up\n")
        pid = _pid(server, crashed["id"])
        server.process.kill()  # SIGKILL: the server dies, its run's process (own session) not
        stop_server(server)
        assert _alive(pid)
        server = restart_server(server)
        with server.admin as c:
            ended = run_of(c, crashed["id"])
            assert ended["state"] == "failed"
            assert ended["error"] == "the server stopped during the run"
            assert log_of(c, crashed["id"]) == (
                "up\n[twinlink] failed: the server stopped during the run\n"
            )
        poll_until(lambda: not _alive(pid), "the dead server's run to be killed at restart")
    finally:
        stop_server(server)


def test_a_script_that_changes_its_files_changes_copies_not_the_library(server: Server) -> None:
    script = "chmod u+w twin.yaml\necho '# changed by the run' >> twin.yaml\ncat twin.yaml\n"
    name = deploy_package(server, {"evolve": script})
    with server.admin as c:
        first = start_run(c, name, "evolve")
        wait_state(server, first["id"], "succeeded")
        assert "# changed by the run" in log_of(c, first["id"])
        r = c.get(f"/api/v1/library/me/twins/{name}/versions/latest/files/twin.yaml")
        assert r.status_code == 200 and "changed" not in r.text  # the library's file as pushed
        second = start_run(c, name, "evolve")
        wait_state(server, second["id"], "succeeded")
        # The deployment's folder is kept across its runs: the second sees the first's change
        # in its copy, and the library's file is still as pushed.
        assert log_of(c, second["id"]).count("# changed by the run") == 2
        r = c.get(f"/api/v1/library/me/twins/{name}/versions/latest/files/twin.yaml")
        assert r.status_code == 200 and "changed" not in r.text
