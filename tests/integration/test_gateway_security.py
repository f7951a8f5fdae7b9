"""The gateway cannot be turned against its services or its secrets: paths that would leave a
service's base URL never reach it, base URLs are checked, and no credential shows up in any
answer, log line, audit entry or file of the data directory."""

from __future__ import annotations

import base64
import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import quote

import httpx
import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from tests.conftest import Server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._gateway import (
    DEFAULT_TWIN,
    add_service,
    echoed,
    gateway_server,
    new_twin,
    path,
    raw_request,
)
from tests.integration._gateway import server as server  # module fixture
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from tests.integration._util import apply, assert_problem, twin_doc, unhandled_errors, unique

pytestmark = pytest.mark.integration
TOKENS = ("oauth", "login")
SECRETS = ("password", "token", "value", "client_secret")
# Ways out of a service's base URL; {m} is a marker the upstream must never see.
ESCAPES = [
    "../{m}",
    "..",
    "a/../../{m}",
    "%2e%2e/{m}",
    "%2E%2e/{m}",
    ".%2e/{m}",
    "%2e./{m}",
    "./{m}",
    "%2e/{m}",
    "..%2f{m}",
    "a%2F..%2F..%2F{m}",
    "a%2f{m}",
    "..%5c{m}",
    "a%5C{m}",
    "a%00{m}",
    "%252e%252e/{m}",
    "%252f{m}",
    "%25252e%25252e/{m}",
    "..;/{m}",
    "%2e%2e;x=1/{m}",
    "/evil.example/{m}",
    "//evil.example/{m}",
    "http://evil.example/{m}",
    "http:%2F%2Fevil.example/{m}",
    "a/http://evil.example/{m}",
    "a\\..\\{m}",
]


@pytest.fixture(scope="module")
def twins(server: Server, upstream: Upstream) -> list[str]:
    """A twin and the default twin, each with service `inner` at the upstream's /open/inner/."""
    slug = new_twin(server)
    new_twin(server, DEFAULT_TWIN)
    with server.admin as admin:
        for twin in (slug, DEFAULT_TWIN):
            add_service(admin, twin, "inner", upstream.base("open") + "inner")
    return [slug, DEFAULT_TWIN]


@pytest.mark.parametrize("escape", ESCAPES)
def test_paths_that_leave_the_service_are_refused(
    server: Server, upstream: Upstream, twins: list[str], escape: str
) -> None:
    marker = unique("escape")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    for prefix in (f"/twins/{twins[0]}/services/inner/", "/services/inner/"):
        for method in ("GET", "POST"):
            status, body = raw_request(server, method, prefix + escape.format(m=marker), headers)
            assert status == 400, (prefix + escape, status, body[:300])
    assert upstream.requests_to(marker) == []


def test_escapes_before_the_service_never_reach_it(
    server: Server, upstream: Upstream, twins: list[str]
) -> None:
    marker = unique("escape")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    for target in (
        f"/twins/{twins[0]}/services/../services/inner/{marker}",
        f"/twins/{twins[0]}/services/inner%2f..%2f/{marker}",
        f"/twins/{twins[0]}/../{twins[0]}/services/inner/{marker}",
        f"/twins/{twins[0]}/services/inner@evil.example/{marker}",
        f"/services/%2e%2e/api/v1/{marker}",
    ):
        status, _ = raw_request(server, "GET", target, headers)
        assert status in (400, 404), (target, status)
    assert upstream.requests_to(marker) == []


def test_an_at_sign_stays_a_path_on_the_service(
    server: Server, upstream: Upstream, twins: list[str]
) -> None:
    marker = unique("at")
    headers = {"Authorization": f"Bearer {server.admin_token}", "Host": "evil.example"}
    for target in (
        path(twins[0], "inner", f"@evil.example/{marker}"),
        path(twins[0], "inner", f"user:pw@evil.example/{marker}"),
        # An absolute-form request target names a host; the gateway goes to the service's.
        f"http://evil.example{path(twins[0], 'inner', marker)}",
    ):
        status, body = raw_request(server, "GET", target, headers)
        assert status == 200, (target, status, body[:300])
    seen = upstream.requests_to(marker)
    assert len(seen) == 3
    for request in seen:
        assert request.raw_path.startswith("/open/inner/"), request.raw_path
        assert request.header("host") == [f"127.0.0.1:{upstream.port}"]


def test_a_websocket_cannot_leave_the_service(
    server: Server, upstream: Upstream, twins: list[str]
) -> None:
    marker = unique("wsescape")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    url = server.url.replace("http://", "ws://") + path(twins[0], "inner", f"..%2f{marker}")
    with pytest.raises(InvalidStatus) as refused:
        connect(url, additional_headers=headers).close()
    assert refused.value.response.status_code == 400
    assert upstream.requests_to(marker) == []


@pytest.mark.parametrize(
    "base_url",
    [
        "ftp://127.0.0.1/files/",
        "file:///etc/passwd",
        "gopher://127.0.0.1:70/",
        "javascript:alert(1)",
        "http:///no-host/",
        "127.0.0.1:8080/api/",
        "http://user:SECRET-in-url@127.0.0.1/api/",
        "http://127.0.0.1:80@evil.example/api/",
        "http://127.0.0.1/api/?token=SECRET-in-query",
        "http://127.0.0.1/api/#fragment",
    ],
)
def test_base_urls_are_http_with_a_host_and_no_credentials(
    server: Server, upstream: Upstream, twins: list[str], base_url: str
) -> None:
    services = f"/api/v1/twins/{twins[0]}/services"
    with server.admin as admin:
        made = admin.post(services, json={"name": unique("bad"), "base_url": base_url})
        patched = admin.patch(f"{services}/inner", json={"base_url": base_url})
        kept = admin.get(f"{services}/inner").json()["base_url"]
    for r in (made, patched):
        problem = assert_problem(r, 422)
        assert "SECRET" not in problem["detail"]
    assert kept == upstream.base("open") + "inner/"


@pytest.mark.parametrize(
    "auth",
    [
        {"method": "bearer", "token": "SECRET\r\n\r\nGET /smuggled HTTP/1.1\r\nHost: x"},
        {"method": "api_key", "name": "X-Api-Key", "value": "SECRET\r\nX-Injected: 1"},
        {"method": "api_key", "name": "X-Api-Key", "value": "SECRET-ключ"},
        {"method": "api_key", "name": "X Api:Key", "value": "SECRET"},
        {"method": "custom_login", "login_url": "ftp://127.0.0.1/", "template": "T {token}"},
        {"method": "custom_login", "login_url": "http://x/", "header": "X Bad"},
        {"method": "custom_login", "login_url": "http://x/", "template": "T\n{token}"},
        {"method": "oauth2_client_credentials", "token_url": "file:///etc/passwd",
         "client_id": "c", "client_secret": "SECRET"},
    ],
)  # fmt: skip
def test_credentials_that_would_break_a_request_are_refused(
    server: Server, upstream: Upstream, twins: list[str], auth: dict[str, Any]
) -> None:
    services = f"/api/v1/twins/{twins[0]}/services"
    with server.admin as admin:
        r = admin.post(
            services, json={"name": "broken", "base_url": upstream.base("open"), "auth": auth}
        )
        assert "SECRET" not in assert_problem(r, 422)["detail"]
        assert_problem(admin.patch(f"{services}/inner", json={"auth": auth}), 422)
        assert admin.get(services).status_code == 200  # the twin's services still work
        echoed(admin.get(path(twins[0], "inner", "echo/x")))
    assert upstream.requests_to("smuggled") == []


@pytest.mark.parametrize(
    "token",
    ["t\r\n\r\nGET /smuggled HTTP/1.1\r\nHost: x", "tøkén-ключ"],
    ids=["line-breaks", "not-latin-1"],
)
def test_a_token_that_cannot_go_in_a_header_is_refused(
    server: Server, upstream: Upstream, token: str
) -> None:
    slug = new_twin(server)
    s = upstream.secrets
    auth = {
        "method": "custom_login",
        "login_url": f"{upstream.url}/_auth/login",
        "body": {"user": s.login_user, "password": s.login_password},
        "token_path": "data.token",
        "template": "Token {token}",
    }
    upstream.next_token = token
    with server.admin as admin:
        add_service(admin, slug, "login", upstream.base("login"), auth=auth)
        problem = assert_problem(admin.get(path(slug, "login", "echo/x")), 502)
        assert problem["code"] == "refresh_failed" and "header" in problem["detail"]
        echoed(admin.get(path(slug, "login", "echo/x")))  # the next token is a good one
    assert upstream.requests_to("smuggled") == []


def test_a_document_service_with_an_unusable_address_is_blocked(server: Server) -> None:
    slug = unique("ftp")
    features = [{"name": "Files", "apiAddress": "ftp://127.0.0.1/files/"}]
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", slug=slug, features=features))
        [listed] = admin.get(f"/api/v1/twins/{slug}/services").json()["services"]
        problem = assert_problem(admin.get(path(slug, "files", "x")), 503)
    assert listed["blocked"] and "apiAddress" in listed["blocked"]
    assert problem["code"] == "failed" and problem["source"] == "gateway"


# -- no secret leaks ------------------------------------------------------------------------


@pytest.fixture
def verbose_server(tmp_path: Path) -> Iterator[Server]:
    """A server logging everything it can (debug level, one line per request)."""
    srv = gateway_server(tmp_path / "data", TWINLINK_LOG_LEVEL="debug", TWINLINK_ACCESS_LOG="1")
    try:
        yield srv
    finally:
        stop_server(srv)


def every_method(upstream: Upstream) -> dict[str, tuple[str, dict[str, Any]]]:
    """Service name -> (realm, auth) for every credential method."""
    s = upstream.secrets
    oauth = {
        "token_url": f"{upstream.url}/_auth/token",
        "client_id": s.client_id,
        "client_secret": s.client_secret,
    }
    login = {
        "method": "custom_login",
        "login_url": f"{upstream.url}/_auth/login",
        "body": {"user": s.login_user, "password": s.login_password},
        "token_path": "data.token",
        "template": "Token {token}",
    }
    basic = {"method": "basic", "username": s.basic_user, "password": s.basic_password}
    key = {"method": "api_key", "name": "X-Api-Key", "value": s.api_key}
    password = {"username": s.oauth_user, "password": s.oauth_password}
    return {
        "basic": ("basic", basic),
        "bearer": ("bearer", {"method": "bearer", "token": s.bearer}),
        "key-header": ("key-header", key),
        "key-query": ("key-query", {**key, "name": "api_key", "in": "query"}),
        "cc-basic": ("oauth", {"method": "oauth2_client_credentials", **oauth}),
        "cc-body": (
            "oauth",
            {"method": "oauth2_client_credentials", **oauth, "client_auth": "body"},
        ),
        "password": ("oauth", {"method": "oauth2_password", **oauth, **password}),
        "login": ("login", login),
    }


def exercise(srv: Server, upstream: Upstream, slug: str) -> list[str]:
    """Use every service every way; the text of every answer the platform gave itself (the
    service's own answers echo the credentials it was sent, as they should)."""
    answers: list[str] = []
    ws = srv.url.replace("http://", "ws://")
    methods = every_method(upstream)

    def forward(admin: httpx.Client, method: str, target: str, status: int) -> None:
        r = admin.request(method, target, content=b"body" if method == "POST" else None)
        assert r.status_code == status, r.text
        if r.headers["content-type"].startswith("application/problem+json"):
            answers.append(r.text)

    with srv.admin as admin:
        for name, (realm, auth) in methods.items():
            answers.append(repr(add_service(admin, slug, name, upstream.base(realm), auth=auth)))
            forward(admin, "GET", path(slug, name, "echo/a?x=1"), 200)
            forward(admin, "POST", path(slug, name, "echo/b"), 200)
            answers.append(admin.get(f"/api/v1/twins/{slug}/services/{name}/health").text)
            with connect(ws + path(slug, name, f"ws?access_token={srv.admin_token}")) as socket:
                socket.send("hi")
                assert socket.recv(timeout=10) == "hi"
        upstream.revoke_all()  # every token method renews
        for name in methods:
            forward(admin, "GET", path(slug, name, "echo/c"), 200)
        upstream.token_endpoints_down = True
        upstream.revoke_all()
        for name, (realm, _) in methods.items():
            forward(admin, "GET", path(slug, name, "echo/d"), 502 if realm in TOKENS else 200)
        upstream.token_endpoints_down = False
        for name, (_, auth) in methods.items():
            wrong = {k: "SECRET-wrong" if k in SECRETS else v for k, v in auth.items()}
            if "body" in auth:
                wrong["body"] = {**auth["body"], "password": "SECRET-wrong"}
            r = admin.patch(f"/api/v1/twins/{slug}/services/{name}", json={"auth": wrong})
            assert r.status_code == 200, r.text
            answers.append(r.text)
            forward(admin, "GET", path(slug, name, "echo/e"), 502)
        answers.append(admin.get(f"/api/v1/twins/{slug}/services").text)
        answers.append(admin.get("/api/v1/gateway/audit", params={"limit": 1000}).text)
        answers.append(admin.get("/metrics").text)
    return answers


def secret_forms(upstream: Upstream) -> list[str]:
    """Each secret as it could be written down: plain, URL-encoded, in a Basic header."""
    s = upstream.secrets
    forms = [*upstream.secrets.values(), *upstream.all_tokens, "SECRET-wrong"]
    forms += [quote(v, safe="") for v in upstream.secrets.values()]
    forms += [
        base64.b64encode(f"{s.basic_user}:{s.basic_password}".encode()).decode(),
        base64.b64encode(
            f"{quote(s.client_id)}:{quote(s.client_secret, safe='')}".encode()
        ).decode(),
    ]
    return sorted(set(forms))


def test_no_secret_is_ever_shown_logged_or_stored_in_clear(
    verbose_server: Server, upstream: Upstream
) -> None:
    slug = new_twin(verbose_server)
    answers = exercise(verbose_server, upstream, slug)
    assert len(upstream.all_tokens) >= 6
    stop_server(verbose_server)  # the whole log is in, the database written out
    assert unhandled_errors(verbose_server) == 0
    log = verbose_server.log()
    assert path(slug, "basic", "echo/a") in log  # the log did see the traffic
    data_dir = verbose_server.data_dir
    files = {
        p: p.read_bytes() for p in data_dir.rglob("*") if p.is_file() and p.name != "secret.key"
    }
    assert data_dir / "twinlink.sqlite3" in files
    for secret in secret_forms(upstream):
        assert secret not in log, f"the log shows {secret[:14]}..."
        for answer in answers:
            assert secret not in answer, f"an answer shows {secret[:14]}...: {answer[:200]}"
        for file, content in files.items():
            assert secret.encode() not in content, f"{file.name} holds {secret[:14]}..."
    key = data_dir / "secret.key"
    assert stat.S_IMODE(os.stat(key).st_mode) == 0o600
    assert key.read_bytes().strip().decode() not in log
