"""The server process: API description, metrics, migrations, restarts, secrets in output."""

from __future__ import annotations

import re
import secrets
import sqlite3
import statistics
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import (
    apply,
    assert_problem,
    make_user,
    twin_count,
    twin_doc,
    unique,
)
from twinlink.auth.secrets import hash_password
from twinlink.store.sqlite.db import connect, migrate, migrations
from twinlink.store.sqlite.store import SqliteStore

pytestmark = pytest.mark.integration

DB_FILE = SqliteStore.FILE_NAME


@pytest.fixture
def servers() -> Iterator[list[Server]]:
    """Servers a test starts itself; all stopped at the end, even when the test fails."""
    started: list[Server] = []
    yield started
    for s in started:
        stop_server(s)


# -- API description and docs --------------------------------------------------------------


def test_openapi_describes_the_api_and_needs_a_token(server: Server) -> None:
    with server.admin as admin:
        r = admin.get("/openapi.json")
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("application/json")
    spec = r.json()
    assert spec["openapi"].startswith("3.")
    assert "/api/v1/twins" in spec["paths"] and "/api/v1/search" in spec["paths"]
    assert {"get", "post"} <= set(spec["paths"]["/api/v1/twins"])
    with server.client() as anon:
        assert_problem(anon.get("/openapi.json"), 401)


def test_docs_page_is_static_and_loads_swagger_from_the_server(server: Server) -> None:
    """/docs needs no token (docs/decisions/0002): a static page without data that asks for a
    token before it loads /openapi.json. Its scripts come from this server, not a CDN."""
    with server.client() as anon:
        page = anon.get("/docs")
        assert page.status_code == 200
        assert page.headers["content-type"].startswith("text/html")
        assert "/api/v1/" not in page.text  # no part of the API description is inlined
        scripts = re.findall(r'<script[^>]+src="([^"]+)"', page.text)
        styles = re.findall(r'<link[^>]+href="([^"]+)"', page.text)
        assert scripts
        for src in scripts + styles:
            assert src.startswith("/"), f"{src} is not served by twinlink"
            asset = anon.get(src)
            assert asset.status_code == 200, src
            assert len(asset.content) > 100


def test_openapi_can_be_opened_to_anonymous_readers_by_setting(
    tmp_path: Path, servers: list[Server]
) -> None:
    srv = start_server(tmp_path, extra_env={"TWINLINK_PUBLIC_API_DOCS": "true"})
    servers.append(srv)
    with srv.client() as anon:
        r = anon.get("/openapi.json")
        assert r.status_code == 200 and "/api/v1/twins" in r.json()["paths"]
        # Opening the description opens nothing else.
        assert_problem(anon.get("/api/v1/twins"), 401)


# -- metrics -------------------------------------------------------------------------------


def _sample(text: str, name: str) -> float:
    [value] = [float(line.split()[-1]) for line in text.splitlines() if line.split(" ")[0] == name]
    return value


def test_metrics_are_prometheus_text(server: Server) -> None:
    secret_slug = unique("not-a-label")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:test:{unique('metric')}", name="Counted"))
        admin.get(f"/twins/{secret_slug}")
        admin.get(f"/{secret_slug}/unmatched/path")
        r = admin.get("/metrics")
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("text/plain")
    text = r.text
    assert "# TYPE twinlink_http_requests_total counter" in text
    assert "twinlink_http_requests_total{" in text
    assert re.search(
        r'twinlink_http_requests_total\{method="POST",route="/api/v1/apply",'
        r'status="200"\} [1-9]',
        text,
    )
    # Labelled by route template, never by the raw path (which would grow without bound).
    assert 'route="/twins/{slug}"' in text
    assert secret_slug not in text
    assert _sample(text, "twinlink_twins") == twin_count(server)
    with server.admin as admin:
        users = len(admin.get("/api/v1/users").json()["users"])
    assert _sample(text, "twinlink_users") == users


def test_metrics_are_for_admins_and_the_metrics_token(
    tmp_path: Path, servers: list[Server]
) -> None:
    # Issue 13, item 9: any signed-in user could read the labels of twins they cannot see.
    metrics_token = "metrics-" + secrets.token_hex(16)
    srv = start_server(
        tmp_path,
        extra_env={
            "TWINLINK_METRICS_TOKEN": metrics_token,
            "TWINLINK_LOG_LEVEL": "debug",
            "TWINLINK_ACCESS_LOG": "true",
        },
    )
    servers.append(srv)
    hidden = unique("hidden")
    with srv.admin as admin:
        apply(admin, twin_doc(f"urn:{hidden}", slug=hidden, privacy="private"))
        r = admin.post(f"/api/v1/twins/{hidden}/processors", json={
            "name": "secret-proc", "blueprint": "expression",
            "params": {"outputs": {"y": "x"}}})  # fmt: skip
        assert r.status_code == 201, r.text
        viewer = make_user(srv, unique("viewer"))
        assert admin.get("/metrics").status_code == 200
    with srv.client(metrics_token) as prometheus:
        r = prometheus.get("/metrics")
        assert r.status_code == 200 and "twinlink_http_requests_total" in r.text
        assert hidden in r.text  # the labels a viewer must not read
        # The metrics token reads the metrics and nothing else.
        assert_problem(prometheus.get("/api/v1/twins"), 401)
    with srv.client(viewer) as c:
        assert hidden not in assert_problem(c.get("/metrics"), 403)["detail"]
    with srv.client() as anonymous:
        assert_problem(anonymous.get("/metrics"), 401)
    with srv.client(metrics_token + "x") as wrong:
        assert_problem(wrong.get("/metrics"), 401)
    stop_server(srv)  # flush everything it would print
    assert metrics_token not in srv.log()


def test_keep_alive_requests_are_answered_promptly(server: Server) -> None:
    """Several requests on one connection (as every client and the CLI send them). A server
    socket without TCP_NODELAY answers each of them only after the peer's delayed-ACK timer
    (about 40 ms on Linux) instead of in a millisecond or two."""
    timings = []
    with server.client() as c:
        c.get("/healthz")
        for _ in range(15):
            start = time.perf_counter()
            assert c.get("/healthz").status_code == 200
            timings.append(time.perf_counter() - start)
    assert statistics.median(timings) < 0.02, [round(t * 1000, 1) for t in timings]


# -- migrations and restarts ---------------------------------------------------------------


def test_migrations_upgrade_an_old_data_dir_in_place(tmp_path: Path, servers: list[Server]) -> None:
    latest = max(version for version, _, _ in migrations())
    assert latest > 1, "this test needs at least one migration after the first"
    password = "pre-existing-password"
    conn = connect(tmp_path / DB_FILE)
    try:
        assert migrate(conn, target=1) == [1]
        assert conn.execute("PRAGMA user_version").fetchone()[0] == 1
        conn.execute(
            "INSERT INTO users(username, password_hash, is_admin, groups_json, created_ns)"
            " VALUES ('admin', ?, 1, '[]', 1700000000000000000)",
            (hash_password(password),),
        )
    finally:
        conn.close()

    srv = start_server(tmp_path)
    servers.append(srv)
    assert "created the first admin" not in srv.log()  # the existing user was kept
    with srv.client() as c:
        r = c.post("/api/v1/auth/login", json={"username": "admin", "password": password})
        assert r.status_code == 200, r.text
    word = "migratedword" + secrets.token_hex(3)
    with srv.admin as admin:  # the preset token was attached to the existing admin
        assert admin.get("/api/v1/auth/me").json()["username"] == "admin"
        users = admin.get("/api/v1/users").json()["users"]
        assert [u["created"] for u in users] == ["2023-11-14T22:13:20.000Z"]
        apply(admin, twin_doc(f"urn:test:{unique('migrated')}", name=f"Twin {word}"))
        found = admin.get("/api/v1/search", params={"q": word})
        assert found.status_code == 200, found.text
        assert [h["name"] for h in found.json()["hits"]] == [f"Twin {word}"]

    check = sqlite3.connect(tmp_path / DB_FILE)
    try:
        assert check.execute("PRAGMA user_version").fetchone()[0] == latest
    finally:
        check.close()


def _printed_token(output: str) -> str | None:
    found = re.findall(r"API token: (\S+)", output)
    assert len(found) <= 1
    return found[0] if found else None


def test_restart_keeps_twins_and_prints_no_new_secrets(
    tmp_path: Path, servers: list[Server]
) -> None:
    no_presets = {"TWINLINK_ADMIN_TOKEN": "", "TWINLINK_ADMIN_PASSWORD": ""}
    first = start_server(tmp_path, extra_env=no_presets)
    servers.append(first)
    token = _printed_token(first.log())
    assert token and token.startswith("tl_")
    assert re.search(r"password: \S+", first.log())
    with first.client(token) as c:
        slug = apply(c, twin_doc(f"urn:test:{unique('kept')}", name="Kept")).json()["results"][0][
            "slug"
        ]
        kept_doc = c.get(f"/twins/{slug}/index.json").json()
    stop_server(first)

    second = start_server(tmp_path, extra_env=no_presets)
    servers.append(second)
    assert _printed_token(second.log()) is None
    assert "created the first admin" not in second.log()
    assert "password:" not in second.log()
    with second.client(token) as c:
        assert c.get("/api/v1/auth/me").status_code == 200
        assert (
            c.get(f"/twins/{slug}/index.json").json()["createdMachine"]
            == kept_doc["createdMachine"]
        )
        assert [u["username"] for u in c.get("/api/v1/users").json()["users"]] == ["admin"]
    stop_server(second)

    # A preset admin token is also accepted on a data dir that already has an admin.
    third = start_server(tmp_path)
    servers.append(third)
    with third.admin as admin:
        assert admin.get("/api/v1/auth/me").json()["username"] == "admin"
        assert admin.get(f"/api/v1/twins/{slug}").status_code == 200
    with third.client(token) as c:
        assert c.get("/api/v1/auth/me").status_code == 200
    assert third.admin_token not in third.log()


# -- secrets are never logged --------------------------------------------------------------


def test_preset_admin_token_works_and_is_not_printed(server: Server) -> None:
    with server.admin as admin:
        me = admin.get("/api/v1/auth/me")
    assert me.status_code == 200
    assert me.json()["username"] == "admin" and me.json()["is_admin"] is True
    assert server.admin_token not in server.log()
    assert server.admin_password not in server.log()


def test_secrets_are_not_logged_even_at_debug_level(tmp_path: Path, servers: list[Server]) -> None:
    srv = start_server(
        tmp_path, extra_env={"TWINLINK_LOG_LEVEL": "debug", "TWINLINK_ACCESS_LOG": "true"}
    )
    servers.append(srv)
    user_password = "user-password-" + secrets.token_hex(4)
    with srv.admin as admin:
        admin.post("/api/v1/users", json={"username": "logged", "password": user_password})
        created = admin.post("/api/v1/tokens", json={"name": "debug"}).json()["token"]
    with srv.client() as c:
        session = c.post(
            "/api/v1/auth/login", json={"username": "logged", "password": user_password}
        ).json()["token"]
        c.post(
            "/api/v1/auth/login", json={"username": "logged", "password": "wrong-" + user_password}
        )
    for token in (created, session, srv.admin_token, "tl_" + "x" * 43):
        with srv.client(token) as c:
            c.get("/api/v1/auth/me")
            c.get("/api/v1/twins", params={"q": "anything"})
    with srv.admin as admin:
        admin.get("/metrics")
    stop_server(srv)  # flush everything it would print
    log = srv.log()
    assert "GET /api/v1/auth/me" in log or "/api/v1/auth/me" in log  # the access log is on
    for secret in (srv.admin_token, srv.admin_password, user_password, created, session):
        assert secret not in log


def test_healthz_reports_the_version(server: Server) -> None:
    import twinlink

    with httpx.Client(base_url=server.url) as c:
        r = c.get("/healthz")
    assert r.status_code == 200
    assert r.json() == {"status": "ok", "version": twinlink.__version__}
