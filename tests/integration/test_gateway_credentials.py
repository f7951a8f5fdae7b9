"""The gateway signs in to services for its callers: every credential method end to end against
a real service, token expiry and renewal on refusal (once for many refused requests), failures
that say so without showing a secret, and services blocked when their address moves."""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Iterator
from typing import Any

import httpx
import pytest
from websockets.sync.client import connect

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._gateway import (
    add_service,
    echoed,
    new_twin,
    path,
    user_with_role,
    wait_until,
)
from tests.integration._gateway import server as server  # module fixture
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from tests.integration._util import apply, assert_problem, twin_doc, unique

pytestmark = pytest.mark.integration


@pytest.fixture(autouse=True)
def fresh_upstream(upstream: Upstream) -> Iterator[None]:
    yield
    upstream.expires_in = 3600.0
    upstream.token_endpoints_down = False


def static_auth(upstream: Upstream, realm: str) -> dict[str, Any]:
    s = upstream.secrets
    return {
        "basic": {"method": "basic", "username": s.basic_user, "password": s.basic_password},
        "bearer": {"method": "bearer", "token": s.bearer},
        "key-header": {"method": "api_key", "name": "X-Api-Key", "value": s.api_key},
        "key-query": {"method": "api_key", "name": "api_key", "value": s.api_key, "in": "query"},
    }[realm]


def oauth(upstream: Upstream, grant: str, client_auth: str = "basic") -> dict[str, Any]:
    s = upstream.secrets
    auth: dict[str, Any] = {
        "method": f"oauth2_{grant}",
        "token_url": f"{upstream.url}/_auth/token",
        "client_id": s.client_id,
        "client_secret": s.client_secret,
        "client_auth": client_auth,
    }
    if grant == "password":
        auth.update(username=s.oauth_user, password=s.oauth_password)
    return auth


def login(upstream: Upstream, password: str | None = None) -> dict[str, Any]:
    s = upstream.secrets
    return {
        "method": "custom_login",
        "login_url": f"{upstream.url}/_auth/login",
        "body": {"user": s.login_user, "password": password or s.login_password},
        "token_path": "data.token",
        "expires_in_path": "data.expires_in",
        "template": "Token {token}",
    }


def service(server: Server, upstream: Upstream, realm: str, auth: dict[str, Any]) -> str:
    """A new twin with service `svc` on `realm`; returns the twin's slug."""
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "svc", upstream.base(realm), auth=auth)
    return slug


@pytest.mark.parametrize("realm", ["basic", "bearer", "key-header", "key-query"])
def test_static_credentials_reach_the_service_alone(
    server: Server, upstream: Upstream, realm: str
) -> None:
    slug = service(server, upstream, realm, static_auth(upstream, realm))
    # The caller's own credentials (its platform token, a key of its own) never arrive.
    forged = {"X-Api-Key": "forged-by-the-client"}
    with server.admin as admin:
        answer = echoed(
            admin.get(path(slug, "svc", "echo/x?api_key=forged&keep=1"), headers=forged)
        )
    names = [k for k, _ in answer["headers"]]
    if realm in ("basic", "bearer"):
        assert names.count("authorization") == 1
    else:
        assert "authorization" not in names
    # A key the caller sends under the credential's name is replaced, not sent alongside.
    if realm == "key-header":
        assert [v for k, v in answer["headers"] if k == "x-api-key"] == [upstream.secrets.api_key]
    if realm == "key-query":
        assert answer["query"] == f"keep=1&api_key={upstream.secrets.api_key}"
    assert server.admin_token not in str(answer)


@pytest.mark.parametrize(
    ("grant", "client_auth"),
    [("client_credentials", "basic"), ("client_credentials", "body"), ("password", "basic")],
)
def test_oauth2_grants_fetch_a_token_once(
    server: Server, upstream: Upstream, grant: str, client_auth: str
) -> None:
    slug = service(server, upstream, "oauth", oauth(upstream, grant, client_auth))
    issued = upstream.issued["oauth"]
    with server.admin as admin:
        for _ in range(3):
            answer = echoed(admin.get(path(slug, "svc", "echo/x")))
            [auth] = [v for k, v in answer["headers"] if k == "authorization"]
            assert auth.startswith("Bearer ") and server.admin_token not in auth
        assert admin.get(f"/api/v1/twins/{slug}/services/svc").json()["credential_refreshes"] == 1
    assert upstream.issued["oauth"] == issued + 1
    assert upstream.grants[-1] == (grant, client_auth)


def test_a_password_grant_without_a_client(server: Server, upstream: Upstream) -> None:
    auth = oauth(upstream, "password")
    del auth["client_id"], auth["client_secret"]
    slug = service(server, upstream, "oauth", auth)
    with server.admin as admin:
        assert echoed(admin.get(path(slug, "svc", "echo/x")))["method"] == "GET"
    assert upstream.grants[-1] == ("password", "none")


def test_a_custom_login_token_in_its_own_format(server: Server, upstream: Upstream) -> None:
    slug = service(server, upstream, "login", login(upstream))
    with server.admin as admin:
        answer = echoed(admin.get(path(slug, "svc", "echo/x")))
        health = admin.get(f"/api/v1/twins/{slug}/services/svc/health").json()
    [auth] = [v for k, v in answer["headers"] if k == "authorization"]
    assert auth.startswith("Token ")
    assert (health["status"], health["http_status"]) == ("up", 200)


@pytest.mark.parametrize("realm", ["oauth", "login"])
def test_a_token_is_renewed_before_it_expires(
    server: Server, upstream: Upstream, realm: str
) -> None:
    upstream.expires_in = 1.0
    auth = oauth(upstream, "client_credentials") if realm == "oauth" else login(upstream)
    slug = service(server, upstream, realm, auth)
    issued, refused = upstream.issued[realm], upstream.refused[realm]
    with server.admin as admin:

        def renewed() -> bool | None:
            echoed(admin.get(path(slug, "svc", "echo/x")))
            return True if upstream.issued[realm] >= issued + 2 else None

        wait_until(renewed, what="a token renewed on expiry")
    # Renewed ahead of expiry: the service never had to refuse a request.
    assert upstream.refused[realm] == refused


@pytest.mark.parametrize("realm", ["oauth", "login"])
def test_a_refused_token_is_renewed_and_the_request_sent_again(
    server: Server, upstream: Upstream, realm: str
) -> None:
    auth = oauth(upstream, "password") if realm == "oauth" else login(upstream)
    slug = service(server, upstream, realm, auth)
    with server.admin as admin:
        echoed(admin.get(path(slug, "svc", "echo/x")))
        issued, refused = upstream.issued[realm], upstream.refused[realm]
        upstream.revoke_all()
        answer = echoed(admin.put(path(slug, "svc", "echo/x"), content=b"kept for the retry"))
        assert answer["body_len"] == len(b"kept for the retry")
        assert (upstream.issued[realm], upstream.refused[realm]) == (issued + 1, refused + 1)
        shown = admin.get(f"/api/v1/twins/{slug}/services/svc").json()
        assert (shown["credential_refreshes"], shown["credential_error"]) == (2, None)


async def test_many_refused_requests_cause_one_renewal(server: Server, upstream: Upstream) -> None:
    slug = service(server, upstream, "oauth", oauth(upstream, "client_credentials"))
    url = server.url + path(slug, "svc", "echo/concurrent")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    limits = httpx.Limits(max_connections=40)
    async with httpx.AsyncClient(headers=headers, timeout=30, limits=limits) as client:
        assert (await client.get(url)).status_code == 200
        issued, refused = upstream.issued["oauth"], upstream.refused["oauth"]
        upstream.revoke_all()
        # All 30 are refused with the old token before any is answered: they must share one
        # renewal, then all be sent again.
        upstream.hold_refusals(30)
        answers = await asyncio.gather(
            *(client.get(url) for _ in range(15)),
            *(client.post(url, content=b"x" * i) for i in range(15)),
        )
    assert [r.status_code for r in answers] == [200] * 30, [r.text for r in answers][:3]
    assert sorted(r.json()["body_len"] for r in answers[15:]) == list(range(15))
    assert upstream.refused["oauth"] == refused + 30
    assert upstream.issued["oauth"] == issued + 1


@pytest.mark.parametrize("realm", ["oauth", "login"])
async def test_many_refused_requests_share_one_failed_renewal(
    server: Server, upstream: Upstream, realm: str
) -> None:
    auth = oauth(upstream, "client_credentials") if realm == "oauth" else login(upstream)
    slug = service(server, upstream, realm, auth)
    url = server.url + path(slug, "svc", "echo/failing")
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    async with httpx.AsyncClient(headers=headers, timeout=30) as client:
        assert (await client.get(url)).status_code == 200
        attempts = upstream.attempts[realm]
        upstream.revoke_all()
        upstream.token_endpoints_down = True
        upstream.hold_refusals(10)
        answers = await asyncio.gather(*(client.get(url) for _ in range(10)))
        # One attempt for the ten: the login endpoint is not hammered while it is down.
        assert upstream.attempts[realm] == attempts + 1
        assert {r.json()["code"] for r in answers} == {"refresh_failed"}
        upstream.token_endpoints_down = False
        assert (await client.get(url)).status_code == 200  # a later request tries again


def test_a_large_streamed_body_is_refused_for_a_retry(server: Server, upstream: Upstream) -> None:
    slug = service(server, upstream, "oauth", oauth(upstream, "client_credentials"))
    big = b"y" * (3 << 20)  # over the 1 MiB the gateway keeps for a retry

    def chunks() -> Iterator[bytes]:
        yield from (big[i : i + 65536] for i in range(0, len(big), 65536))

    with server.admin as admin:
        echoed(admin.get(path(slug, "svc", "echo/x")))
        issued = upstream.issued["oauth"]
        upstream.revoke_all()
        r = admin.post(path(slug, "svc", "echo/big"), content=chunks())
        assert assert_problem(r, 503)["code"] == "renewed"
        assert r.headers["retry-after"] == "0"
        assert upstream.issued["oauth"] == issued + 1
        answer = echoed(admin.post(path(slug, "svc", "echo/big"), content=chunks()))
        assert answer["body_len"] == len(big)


def test_a_failed_renewal_is_a_502_that_shows_no_secret(server: Server, upstream: Upstream) -> None:
    slug = service(server, upstream, "oauth", oauth(upstream, "password"))
    with server.admin as admin:
        echoed(admin.get(path(slug, "svc", "echo/x")))
        upstream.revoke_all()
        upstream.token_endpoints_down = True
        problem = assert_problem(admin.get(path(slug, "svc", "echo/x")), 502)
        assert (problem["code"], problem["source"]) == ("refresh_failed", "gateway")
        assert "503" in problem["detail"]
        shown = admin.get(f"/api/v1/twins/{slug}/services/svc").json()
        assert "503" in shown["credential_error"]
        upstream.token_endpoints_down = False
        echoed(admin.get(path(slug, "svc", "echo/x")))  # the next request renews
    assert_no_secret(upstream, problem, shown)


@pytest.mark.parametrize("method", ["client_credentials", "password", "custom_login"])
def test_wrong_login_secrets_are_a_502_that_shows_none(
    server: Server, upstream: Upstream, method: str
) -> None:
    wrong = "SECRET-wrong:+/" + unique("x")
    if method == "custom_login":
        auth = login(upstream, password=wrong)
    else:
        auth = {**oauth(upstream, method), "client_secret": wrong}
    slug = service(server, upstream, "login" if method == "custom_login" else "oauth", auth)
    with server.admin as admin:
        problem = assert_problem(admin.get(path(slug, "svc", "echo/x")), 502)
        shown = admin.get(f"/api/v1/twins/{slug}/services/svc").json()
    assert problem["code"] == "refresh_failed" and "401" in problem["detail"]
    # The upstream echoed the wrong secret in its error; the gateway scrubbed it.
    assert wrong not in str(problem) and wrong not in str(shown)
    assert_no_secret(upstream, problem, shown)


@pytest.mark.parametrize("realm", ["basic", "bearer", "key-header", "key-query"])
def test_refused_static_credentials_cannot_be_renewed(
    server: Server, upstream: Upstream, realm: str
) -> None:
    auth = static_auth(upstream, realm)
    secret_field = {"basic": "password", "bearer": "token"}.get(realm, "value")
    wrong = "SECRET-stale-" + unique("x")
    slug = service(server, upstream, realm, {**auth, secret_field: wrong})
    with server.admin as admin:
        problem = assert_problem(admin.get(path(slug, "svc", "echo/x")), 502)
    assert problem["code"] == "refresh_failed" and "owner" in problem["detail"]
    assert wrong not in str(problem)


def moved_twin(slug: str) -> Callable[[str | None], str]:
    """The DT document of twin `slug`, with feature "Api" at the given address (or none)."""

    def document(base: str | None) -> str:
        features = [] if base is None else [{"name": "Api", "apiAddress": base}]
        return twin_doc(f"urn:{slug}", slug=slug, features=features)

    return document


def test_a_moved_service_is_blocked_until_its_credentials_are_set_again(
    server: Server, upstream: Upstream
) -> None:
    slug = unique("moved")
    document, api = moved_twin(slug), f"/api/v1/twins/{slug}/services/api"
    bearer = static_auth(upstream, "bearer")
    _, editor = user_with_role(server, slug=new_twin(server, slug), role="editor")
    with server.admin as admin:
        apply(admin, document(upstream.base("bearer")))
        r = admin.patch(api, json={"auth": bearer})
        assert r.status_code == 200 and r.json()["blocked"] is None, r.text
        echoed(admin.get(path(slug, "api", "echo/x")))
        # Another path at the same origin: the credentials still belong there.
        apply(admin, document(upstream.base("bearer") + "v2"))
        assert echoed(admin.get(path(slug, "api", "echo/x")))["path"] == "/bearer/v2/echo/x"
    # An editor points the feature at another origin: the credentials are not sent there...
    with server.client(editor) as c:
        apply(c, document(upstream.base("bearer", other=True)))
    marker = unique("moved")
    with server.admin as admin:
        problem = assert_problem(admin.get(path(slug, "api", f"echo/{marker}")), 503)
        assert "set them again" in problem["detail"]
        shown = admin.get(api).json()
        assert shown["blocked"] and shown["auth"]["token_set"] is True
        # ... not after an owner changes another setting either ...
        assert admin.patch(api, json={"description": "moved"}).json()["blocked"]
        assert_problem(admin.get(path(slug, "api", f"echo/{marker}")), 503)
        assert upstream.requests_to(marker) == []
        # ... only once an owner sets them again.
        assert admin.patch(api, json={"auth": bearer}).json()["blocked"] is None
        echoed(admin.get(path(slug, "api", f"echo/{marker}")))
    [seen] = upstream.requests_to(marker)
    assert seen.header("host") == [f"127.0.0.1:{upstream.other_port}"]


def test_credentials_set_while_the_feature_was_gone_are_blocked(
    server: Server, upstream: Upstream
) -> None:
    slug = unique("gone")
    document, api = moved_twin(slug), f"/api/v1/twins/{slug}/services/api"
    with server.admin as admin:
        apply(admin, document(upstream.base("open")))
        assert admin.patch(api, json={"methods": ["GET"]}).status_code == 200
        apply(admin, document(None))
        r = admin.patch(api, json={"auth": static_auth(upstream, "bearer")})
        assert r.status_code == 200 and r.json()["blocked"], r.text
        apply(admin, document(upstream.base("bearer")))
        assert_problem(admin.get(path(slug, "api", "echo/x")), 503)
        assert admin.patch(api, json={"auth": static_auth(upstream, "bearer")}).status_code == 200
        echoed(admin.get(path(slug, "api", "echo/x")))


def test_a_websocket_signs_in_and_renews_a_refused_token(
    server: Server, upstream: Upstream
) -> None:
    slug = service(server, upstream, "login", login(upstream))
    url = server.url.replace("http://", "ws://") + path(slug, "svc", "ws")
    headers = {"Authorization": f"Bearer {server.admin_token}"}

    def echo_once() -> None:
        with connect(url, additional_headers=headers, open_timeout=10) as ws:
            ws.send("hello")
            assert ws.recv(timeout=10) == "hello"

    echo_once()
    issued, refused = upstream.issued["login"], upstream.refused["login"]
    upstream.revoke_all()
    echo_once()
    assert (upstream.issued["login"], upstream.refused["login"]) == (issued + 1, refused + 1)


def assert_no_secret(upstream: Upstream, *shown: Any) -> None:
    text = str(shown)
    for secret in upstream.secrets.values():
        assert secret not in text, f"a secret is shown: {secret[:12]}..."
