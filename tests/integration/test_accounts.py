"""Service accounts, session revocation, owner protection, and request-level rules."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from tests.conftest import Server
from tests.integration._util import (
    YAML_HEADERS,
    apply,
    assert_problem,
    login,
    make_user,
    twin_count,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration


def test_service_account_gets_a_token_from_an_admin(server: Server) -> None:
    name = unique("svc")
    with server.admin as admin:
        assert admin.post("/api/v1/users", json={"username": name}).status_code == 201
        r = admin.post(f"/api/v1/users/{name}/tokens", json={"name": "predictive maintenance"})
    assert r.status_code == 201, r.text
    token = r.json()["token"]
    with server.client(token) as c:
        assert c.get("/api/v1/auth/me").json()["username"] == name
    with server.client() as anon:  # no password: it cannot sign in
        r = anon.post("/api/v1/auth/login", json={"username": name, "password": "anything-at-all"})
    body = assert_problem(r, 401)
    assert "Bearer" not in body["detail"]


def test_only_admins_issue_tokens_for_others(server: Server) -> None:
    alice = unique("alice")
    token = make_user(server, alice)
    with server.client(token) as c:
        assert_problem(c.post("/api/v1/users/admin/tokens", json={"name": "x"}), 403)


def test_new_password_ends_sessions_but_keeps_api_tokens(server: Server) -> None:
    bob = unique("bob")
    session = make_user(server, bob, password="first-password")
    with server.client(session) as c:
        api_token = c.post("/api/v1/tokens", json={"name": "ci"}).json()["token"]
    with server.admin as admin:
        r = admin.patch(f"/api/v1/users/{bob}", json={"password": "second-password"})
        assert r.status_code == 200, r.text
    with server.client(session) as c:
        assert_problem(c.get("/api/v1/auth/me"), 401)
    with server.client(api_token) as c:
        assert c.get("/api/v1/auth/me").status_code == 200
    assert login(server, bob, "second-password")
    with server.client(api_token) as c:
        states = {t["name"]: t["state"] for t in c.get("/api/v1/tokens").json()["tokens"]}
    assert states["ci"] == "active" and states["login session"] in ("revoked", "active")


# -- changing a password ----------------------------------------------------------------------


def _change_password(server: Server, token: str, username: str, **body: str) -> httpx.Response:
    with server.client(token) as c:
        return c.patch(f"/api/v1/users/{username}", json=body)


def _can_sign_in(server: Server, username: str, password: str) -> bool:
    with server.client() as c:
        r = c.post("/api/v1/auth/login", json={"username": username, "password": password})
    return r.status_code == 200


def test_own_password_change_needs_the_current_password(server: Server) -> None:
    name = unique("dave")
    session = make_user(server, name, password="daves-password-1")
    missing = _change_password(server, session, name, password="daves-password-2")
    assert "current_password" in assert_problem(missing, 422)["detail"]
    empty = _change_password(
        server, session, name, password="daves-password-2", current_password=""
    )
    assert_problem(empty, 422)
    wrong = _change_password(
        server, session, name, password="daves-password-2", current_password="not-the-one"
    )
    assert "current password is wrong" in assert_problem(wrong, 403)["detail"]
    # Nothing changed: the old password still signs in and this session still works.
    assert not _can_sign_in(server, name, "daves-password-2")
    assert _can_sign_in(server, name, "daves-password-1")
    with server.client(session) as c:
        assert c.get("/api/v1/auth/me").status_code == 200
    right = _change_password(
        server, session, name, password="daves-password-2", current_password="daves-password-1"
    )
    assert right.status_code == 200, right.text
    assert _can_sign_in(server, name, "daves-password-2")
    assert not _can_sign_in(server, name, "daves-password-1")


def test_an_admin_needs_it_for_their_own_password_only(server: Server) -> None:
    boss, other = unique("boss"), unique("erin")
    session = make_user(server, boss, password="bosss-password-1", is_admin=True)
    make_user(server, other, password="erins-password-1")
    # Another user's password: no current password needed (nor known).
    r = _change_password(server, session, other, password="erins-password-2")
    assert r.status_code == 200, r.text
    assert _can_sign_in(server, other, "erins-password-2")
    # Their own (the name in any case): the same rule as for everyone.
    own = _change_password(server, session, boss.upper(), password="bosss-password-2")
    assert_problem(own, 422)
    assert _can_sign_in(server, boss, "bosss-password-1")


def test_a_user_without_a_password_sets_one_without_the_current_one(server: Server) -> None:
    name = unique("tokenonly")
    with server.admin as admin:
        assert admin.post("/api/v1/users", json={"username": name}).status_code == 201
        token = admin.post(f"/api/v1/users/{name}/tokens", json={"name": "t"}).json()["token"]
    r = _change_password(server, token, name, password="first-password-1")
    assert r.status_code == 200, r.text
    assert _can_sign_in(server, name, "first-password-1")
    # Now there is one, the next change needs it.
    again = _change_password(server, token, name, password="second-password-2")
    assert_problem(again, 422)


def _cli_as(
    server: Server, token: str, tmp_path: Path, *args: str, typed: str | None = None
) -> subprocess.CompletedProcess[str]:
    """The real command as `token`'s user. In a session of its own it has no terminal, so
    its hidden prompt reads `typed` from stdin (and warns that it cannot hide it)."""
    env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_TOKEN": token}
    env["XDG_CONFIG_HOME"] = str(tmp_path)
    return subprocess.run(
        [sys.executable, "-m", "twinlink", *args],
        env=env,
        input=typed,
        stdin=None if typed is not None else subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=60,
        start_new_session=True,
    )


def test_cli_asks_for_the_current_password_of_your_own(server: Server, tmp_path: Path) -> None:
    name = unique("frank")
    session = make_user(server, name, password="franks-password-1")
    change = ("users", "set", name, "--password", "franks-password-2")
    wrong = _cli_as(server, session, tmp_path, *change, typed="not-the-one\n")
    assert wrong.returncode == 1 and "current password is wrong" in wrong.stderr
    assert "Current password" in wrong.stdout + wrong.stderr
    assert "not-the-one" not in wrong.stdout + wrong.stderr
    right = _cli_as(server, session, tmp_path, *change, typed="franks-password-1\n")
    assert right.returncode == 0, right.stderr
    assert f"updated user {name}" in right.stdout
    assert _can_sign_in(server, name, "franks-password-2")


def test_cli_does_not_ask_when_an_admin_changes_another_user(
    server: Server, tmp_path: Path
) -> None:
    name = unique("grace")
    make_user(server, name, password="graces-password-1")
    # stdin is empty: a prompt would fail the command.
    r = _cli_as(
        server, server.admin_token, tmp_path, "users", "set", name, "--password", "graces-pw-2"
    )
    assert r.returncode == 0, r.stderr
    assert "Current password" not in r.stdout + r.stderr
    assert _can_sign_in(server, name, "graces-pw-2")


def test_the_last_owner_stays(server: Server) -> None:
    slug = unique("owned")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Owned", slug=slug))
        assert_problem(admin.delete(f"/api/v1/twins/{slug}/roles/admin"), 409)
        assert_problem(admin.put(f"/api/v1/twins/{slug}/roles/admin", json={"role": "viewer"}), 409)
        other = unique("carol")
        make_user(server, other)
        assert admin.put(f"/api/v1/twins/{slug}/roles/{other}", json={"role": "owner"}).is_success
        assert admin.delete(f"/api/v1/twins/{slug}/roles/admin").is_success


def test_two_new_twins_asking_for_one_slug_store_nothing(server: Server) -> None:
    slug = unique("same")
    before = twin_count(server)
    with server.admin as admin:
        r = apply(
            admin,
            twin_doc(f"urn:{slug}:1", name="One", slug=slug),
            twin_doc(f"urn:{slug}:2", name="Two", slug=slug),
            expect=None,
        )
    assert_problem(r, 409)
    assert twin_count(server) == before


def test_deeply_nested_json_is_refused(server: Server) -> None:
    nested: dict[str, object] = {"leaf": 1}
    for _ in range(100):
        nested = {"n": nested}
    body = {"version": "1.0", "privacy": "public", "name": "deep", "custom": nested}
    with server.admin as admin:
        r = admin.post(
            "/api/v1/apply", content=json.dumps(body), headers={"Content-Type": "application/json"}
        )
    assert "nested more than 64" in str(assert_problem(r, 422)["errors"])


def test_privacy_in_capitals_means_the_fixed_level(server: Server) -> None:
    slug = unique("caps")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Caps", slug=slug, privacy="PUBLIC"))
    with server.client() as anon:
        assert anon.get(f"/twins/{slug}", headers={"Accept": "application/json"}).status_code == 200


def test_cli_users_add_without_password_and_token_for_it(server: Server, tmp_path) -> None:  # type: ignore[no-untyped-def]
    env = {
        **os.environ,
        "TWINLINK_URL": server.url,
        "TWINLINK_TOKEN": server.admin_token,
        "XDG_CONFIG_HOME": str(tmp_path),
    }
    name = unique("robot")

    def cli(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "twinlink", *args],
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            stdin=subprocess.DEVNULL,
        )

    assert cli("users", "add", name, "--no-password").returncode == 0
    made = cli("tokens", "create", "robot-token", "--user", name)
    assert made.returncode == 0, made.stderr
    with server.client(made.stdout.strip()) as c:
        assert c.get("/api/v1/auth/me").json()["username"] == name


def test_put_with_yaml_of_two_twins_is_refused(server: Server) -> None:
    slug = unique("put")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="P", slug=slug))
    body = twin_doc(f"urn:{slug}", name="P") + "---\n" + twin_doc(f"urn:{slug}:other", name="Q")
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}", content=body, headers=YAML_HEADERS)
    assert_problem(r, 422)


def test_a_group_cannot_be_named_like_a_fixed_level(server: Server) -> None:
    with server.admin as admin:
        for name in ("private", "Public"):
            r = admin.post("/api/v1/users", json={"username": unique("g"), "groups": [name]})
            assert "privacy level" in str(assert_problem(r, 422)["errors"])
