"""Devices: who may manage them, and what a device token may do (only its own routes)."""

from __future__ import annotations

import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration


def _twin_with_roles(server: Server) -> tuple[str, dict[str, str]]:
    slug = unique("dev")
    tokens = {role: make_user(server, unique(role)) for role in ("viewer", "editor", "none")}
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, privacy="group-x"))
        for role in ("viewer", "editor"):
            name = admin.get("/api/v1/auth/me", headers={"Authorization": f"Bearer {tokens[role]}"})
            r = admin.put(
                f"/api/v1/twins/{slug}/roles/{name.json()['username']}", json={"role": role}
            )
            assert r.status_code == 200, r.text
    return slug, tokens


def test_editors_add_devices_and_the_token_is_shown_once(server: Server) -> None:
    slug, tokens = _twin_with_roles(server)
    with server.client(tokens["editor"]) as editor:
        r = editor.post(
            f"/api/v1/twins/{slug}/devices", json={"name": "tingenSAP", "description": "rig"}
        )
        assert r.status_code == 201, r.text
        token = r.json()["token"]
        assert token.startswith("tld_") and r.json()["token_prefix"] == token[:9]
        listed = editor.get(f"/api/v1/twins/{slug}/devices")
    assert [d["name"] for d in listed.json()["devices"]] == ["tingenSAP"]
    assert token not in listed.text
    with server.client(token) as device:
        me = device.get("/api/v1/device").json()
    assert (me["twin"], me["name"]) == (slug, "tingenSAP") and me["last_seen"]


def test_roles_for_device_management(server: Server) -> None:
    slug, tokens = _twin_with_roles(server)
    with server.admin as admin:
        assert admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "d1"}).status_code == 201
    with server.client(tokens["viewer"]) as viewer:
        assert viewer.get(f"/api/v1/twins/{slug}/devices").status_code == 200
        assert viewer.get(f"/api/v1/twins/{slug}/devices/d1").status_code == 200
        assert_problem(viewer.post(f"/api/v1/twins/{slug}/devices", json={"name": "d2"}), 403)
        assert_problem(viewer.post(f"/api/v1/twins/{slug}/devices/d1/token"), 403)
        assert_problem(viewer.delete(f"/api/v1/twins/{slug}/devices/d1"), 403)
    with server.client(tokens["none"]) as stranger:  # the twin is not public: it is hidden
        assert_problem(stranger.get(f"/api/v1/twins/{slug}/devices"), 404)


def test_device_tokens_work_only_on_device_routes(server: Server) -> None:
    slug, tokens = _twin_with_roles(server)
    with server.client(tokens["editor"]) as editor:
        token = editor.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}).json()["token"]
        assert_problem(editor.get("/api/v1/device"), 401)  # a user token is not a device token
    with server.client(token) as device:
        assert_problem(device.get("/api/v1/auth/me"), 401)
        assert_problem(device.get(f"/api/v1/twins/{slug}"), 401)
        assert_problem(device.get("/api/v1/twins"), 401)


def test_rotation_and_removal_end_the_old_token(server: Server) -> None:
    slug, tokens = _twin_with_roles(server)
    with server.client(tokens["editor"]) as editor:
        first = editor.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}).json()["token"]
        second = editor.post(f"/api/v1/twins/{slug}/devices/d/token").json()["token"]
        assert first != second
        with server.client(first) as old, server.client(second) as new:
            assert_problem(old.get("/api/v1/device"), 401)
            assert new.get("/api/v1/device").status_code == 200
            assert editor.delete(f"/api/v1/twins/{slug}/devices/d").status_code == 200
            assert_problem(new.get("/api/v1/device"), 401)
        assert_problem(editor.get(f"/api/v1/twins/{slug}/devices/d"), 404)


def test_names_are_checked_and_unique_per_twin(server: Server) -> None:
    slug, tokens = _twin_with_roles(server)
    with server.client(tokens["editor"]) as editor:
        assert editor.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}).status_code == 201
        assert_problem(editor.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}), 409)
        assert_problem(editor.post(f"/api/v1/twins/{slug}/devices", json={"name": "bad name"}), 422)


def test_deleting_the_twin_removes_its_devices(server: Server) -> None:
    slug, _ = _twin_with_roles(server)
    with server.admin as admin:
        token = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}).json()["token"]
        assert admin.delete(f"/api/v1/twins/{slug}").status_code == 200
    with server.client(token) as device:
        assert_problem(device.get("/api/v1/device"), 401)


def test_cli_manages_devices(server: Server, tmp_path) -> None:  # type: ignore[no-untyped-def]
    import os
    import subprocess
    import sys

    slug, _ = _twin_with_roles(server)
    env = {
        **os.environ,
        "TWINLINK_URL": server.url,
        "TWINLINK_TOKEN": server.admin_token,
        "XDG_CONFIG_HOME": str(tmp_path),
    }

    def cli(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "twinlink", "devices", *args],
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            stdin=subprocess.DEVNULL,
        )

    added = cli("add", slug, "rig-1", "-d", "the test rig")
    assert added.returncode == 0, added.stderr
    token = added.stdout.strip()
    with server.client(token) as device:
        assert device.get("/api/v1/device").json()["name"] == "rig-1"
    listed = cli("ls", slug)
    assert "rig-1" in listed.stdout and token not in listed.stdout
    assert cli("rm", slug, "rig-1").returncode == 0
    missing = cli("rm", slug, "rig-1")
    assert missing.returncode == 1 and "Traceback" not in missing.stderr
