"""The gateway's access rules end to end: who may call a service (401, 403, 404, 405 in the
paper's order; a twin the caller may not see is the same 404 as a missing one), the default
twin, services from the DT document, the registry API and its rights, write-only secrets,
service accounts, the audit log and the metrics."""

from __future__ import annotations

import time
from typing import Any

import httpx
import pytest
from prometheus_client.parser import text_string_to_metric_families
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._gateway import (
    DEFAULT_TWIN,
    add_service,
    echoed,
    new_twin,
    path,
    user_with_role,
)
from tests.integration._gateway import server as server  # module fixture
from tests.integration._live import ws_url
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from tests.integration._util import apply, assert_problem, twin_doc, unique

pytestmark = pytest.mark.integration


def gateway_problem(r: httpx.Response, status: int, code: str | None = None) -> dict[str, Any]:
    body = assert_problem(r, status)
    assert body["source"] == "gateway", body
    if code is not None:
        assert body["code"] == code, body
    return body


@pytest.fixture(scope="module")
def twin(server: Server, upstream: Upstream) -> str:
    """A twin with `echo` (every method) and `readonly` (GET only) services."""
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"))
        add_service(admin, slug, "readonly", upstream.base("open"), methods=["GET"])
    return slug


def test_the_checks_come_in_the_papers_order(server: Server, upstream: Upstream, twin: str) -> None:
    _, viewer = user_with_role(server, twin, "viewer")
    _, editor = user_with_role(server, twin, "editor")
    _, stranger = user_with_role(server, twin, None)
    marker = unique("order")
    echo, nowhere = path(twin, "echo", f"echo/{marker}"), path("no-such-twin", "echo", marker)
    with server.client() as anonymous:
        # No token: 401 before anything else, even for a twin or service that does not exist.
        gateway_problem(anonymous.get(echo), 401, "refused")
        gateway_problem(anonymous.get(nowhere), 401)
    with server.client("tl_not_a_real_token") as forged:
        gateway_problem(forged.get(echo), 401)
    with server.client(viewer) as c:
        assert echoed(c.get(echo))["method"] == "GET"
        assert c.head(echo).status_code == 200
        gateway_problem(c.post(echo, content=b"x"), 403)
        # The right is checked before the service is looked up: no probing for names.
        gateway_problem(c.post(path(twin, "no-such-service", marker)), 403)
        gateway_problem(c.get(path(twin, "no-such-service", marker)), 404)
    with server.client(editor) as c:
        answer = echoed(c.post(echo, content=b"payload"))
        assert (answer["method"], answer["body_len"]) == ("POST", 7)
        for method in ("PUT", "PATCH", "DELETE"):
            assert c.request(method, echo).status_code == 200
        r = c.post(path(twin, "readonly", marker), content=b"x")
        gateway_problem(r, 405)
        assert r.headers["allow"] == "GET"
    with server.client(stranger) as c:
        # No role on a twin whose public part anyone may read: 403. No such twin: 404, the
        # answer for a twin the caller may not see too (test_hidden_twins_are_not_found).
        assert gateway_problem(c.get(echo), 403)["detail"]
        gateway_problem(c.get(nowhere), 404)
    with server.admin as admin:
        gateway_problem(admin.get(nowhere), 404)
        gateway_problem(admin.get(path(twin, "no-such-service")), 404)
    seen = upstream.requests_to(marker)
    assert sorted(s.method for s in seen) == ["DELETE", "GET", "HEAD", "PATCH", "POST", "PUT"]


def _hidden_answers(c: httpx.Client, slug: str, service: str) -> list[tuple[str, int, str]]:
    """(route, status, detail with the slug taken out) of every route that names the twin's
    services: the registry API, service accounts, and calls through the gateway."""
    api = f"/api/v1/twins/{slug}"
    requests = [
        ("list", c.get(f"{api}/services")),
        ("get", c.get(f"{api}/services/{service}")),
        ("health", c.get(f"{api}/services/{service}/health")),
        ("create", c.post(f"{api}/services", json={"name": "x", "base_url": "http://a.b/"})),
        ("change", c.patch(f"{api}/services/{service}", json={"description": "x"})),
        ("delete", c.delete(f"{api}/services/{service}")),
        ("accounts", c.get(f"{api}/service-accounts")),
        ("call", c.get(path(slug, service, "echo/x"))),
        ("call post", c.post(path(slug, service, "echo/x"), content=b"x")),
    ]
    out = []
    for route, r in requests:
        body = assert_problem(r, r.status_code)
        out.append((route, r.status_code, body["detail"].replace(slug, "<slug>")))
    return out


def test_hidden_twins_are_not_found_like_missing_ones(server: Server, upstream: Upstream) -> None:
    # Issue 13, item 10: these routes answered 403 for both, where the rest of the API says
    # 404 (a twin the caller may not see is not admitted to exist).
    hidden = new_twin(server, privacy="private")
    with server.admin as admin:
        add_service(admin, hidden, "echo", upstream.base("open"))
    _, stranger = user_with_role(server, hidden, None)
    missing = unique("no-such-twin")
    for token in (stranger, server.admin_token):
        with server.client(token) as c:
            gone = _hidden_answers(c, missing, "echo")
            assert {status for _, status, _ in gone} == {404}, gone
            if token == stranger:
                assert _hidden_answers(c, hidden, "echo") == gone
    headers = {"Authorization": f"Bearer {stranger}"}
    for slug in (hidden, missing):
        with pytest.raises(InvalidStatus) as refused:
            connect(ws_url(server, path(slug, "echo", "ws")), additional_headers=headers).close()
        assert refused.value.response.status_code == 404


def test_the_default_twin_has_short_paths(server: Server, upstream: Upstream) -> None:
    new_twin(server, DEFAULT_TWIN)
    marker = unique("default")
    with server.admin as admin:
        add_service(admin, DEFAULT_TWIN, "echo", upstream.base("open"))
        answer = echoed(admin.get(f"/services/echo/echo/{marker}?q=1"))
        assert answer["path"] == f"/open/echo/{marker}"
        prefixes = [v for k, v in answer["headers"] if k == "x-forwarded-prefix"]
        assert prefixes == ["/services/echo"]
        gateway_problem(admin.get("/services/no-such-service/x"), 404)
    _, stranger = user_with_role(server, DEFAULT_TWIN, None)
    with server.client(stranger) as c:
        gateway_problem(c.get(f"/services/echo/echo/{marker}"), 403)
    with server.client() as anonymous:
        gateway_problem(anonymous.get(f"/services/echo/echo/{marker}"), 401)
    assert len(upstream.requests_to(marker)) == 1


def test_features_with_an_api_address_become_services(server: Server, upstream: Upstream) -> None:
    slug = unique("doc")
    features = [
        {"name": "Sensor Manager (v2)", "apiAddress": upstream.base("open") + "sensors"},
        {"name": "Manual", "documentation": "http://example.org/manual.pdf"},
    ]
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", slug=slug, features=features))
        listed = admin.get(f"/api/v1/twins/{slug}/services").json()["services"]
        assert [(s["name"], s["source"], s["feature"]) for s in listed] == [
            ("sensor-manager-v2", "document", "Sensor Manager (v2)")
        ]
        assert listed[0]["base_url"] == upstream.base("open") + "sensors/"
        answer = echoed(admin.get(path(slug, "sensor-manager-v2", "echo/a?b=c")))
        assert (answer["path"], answer["query"]) == ("/open/sensors/echo/a", "b=c")
        # The URL of a document service is the feature's: it changes in the document only.
        r = admin.patch(
            f"/api/v1/twins/{slug}/services/sensor-manager-v2", json={"base_url": upstream.url}
        )
        assert_problem(r, 422)
        r = admin.patch(
            f"/api/v1/twins/{slug}/services/sensor-manager-v2", json={"methods": ["GET"]}
        )
        assert r.status_code == 200 and r.json()["methods"] == ["GET"], r.text
        gateway_problem(admin.post(path(slug, "sensor-manager-v2", "echo/a")), 405)
        # Deleting a document service resets its settings; the feature keeps it listed.
        r = admin.delete(f"/api/v1/twins/{slug}/services/sensor-manager-v2")
        assert r.json()["outcome"] == "reset", r.text
        assert echoed(admin.post(path(slug, "sensor-manager-v2", "echo/a")))["method"] == "POST"
        # The feature leaves the document: the service is gone.
        apply(admin, twin_doc(f"urn:{slug}", slug=slug, features=features[1:]))
        assert admin.get(f"/api/v1/twins/{slug}/services").json()["services"] == []
        gateway_problem(admin.get(path(slug, "sensor-manager-v2", "echo/a")), 404)


def test_only_owners_change_the_registry(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    service = {"name": "svc", "base_url": upstream.base("open")}
    _, owner = user_with_role(server, slug, "owner")
    _, editor = user_with_role(server, slug, "editor")
    _, viewer = user_with_role(server, slug, "viewer")
    _, stranger = user_with_role(server, slug, None)
    services = f"/api/v1/twins/{slug}/services"
    for token in (editor, viewer):
        with server.client(token) as c:
            assert_problem(c.post(services, json=service), 403)
    with server.client(owner) as c:
        assert c.post(services, json=service).status_code == 201
        assert_problem(c.post(services, json=service), 409)
        assert_problem(c.post(services, json={**service, "name": "Bad Name"}), 422)
    for token in (editor, viewer):
        with server.client(token) as c:
            assert [s["name"] for s in c.get(services).json()["services"]] == ["svc"]
            assert c.get(f"{services}/svc").json()["name"] == "svc"
            assert_problem(c.patch(f"{services}/svc", json={"description": "x"}), 403)
            assert_problem(c.delete(f"{services}/svc"), 403)
    with server.client(stranger) as c:
        assert_problem(c.get(services), 403)
    with server.client(owner) as c:
        r = c.patch(f"{services}/svc", json={"description": "the echo", "limits": {"timeout_s": 9}})
        assert (r.json()["description"], r.json()["limits"]["timeout_s"]) == ("the echo", 9)
        assert r.json()["limits"]["max_body_mb"] == 100  # limits not named are kept
        assert c.delete(f"{services}/svc").json()["outcome"] == "deleted"
        assert_problem(c.get(f"{services}/svc"), 404)


def test_secrets_are_write_only(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    s = upstream.secrets
    auth = {"method": "basic", "username": s.basic_user, "password": s.basic_password}
    answers: list[str] = []
    with server.admin as admin:
        made = add_service(admin, slug, "basic", upstream.base("basic"), auth=auth)
        assert made["auth"] == {"method": "basic", "username": s.basic_user, "password_set": True}
        services = f"/api/v1/twins/{slug}/services"
        answers += [admin.get(services).text, admin.get(f"{services}/basic").text]
        # Settings changed without `auth`, or `auth` of the same method without the secret:
        # the stored password is kept and still works.
        for patch in (
            {"description": "x"},
            {"auth": {"method": "basic", "username": s.basic_user}},
        ):
            r = admin.patch(f"{services}/basic", json=patch)
            assert r.json()["auth"]["password_set"] is True, r.text
            answers.append(r.text)
            assert echoed(admin.get(path(slug, "basic", "echo/x")))["method"] == "GET"
        # Another method needs its own secret.
        r = admin.patch(f"{services}/basic", json={"auth": {"method": "bearer"}})
        answers.append(str(assert_problem(r, 422)))
    for answer in answers:
        assert s.basic_password not in answer


def test_service_accounts_act_within_their_role(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    accounts = f"/api/v1/twins/{slug}/service-accounts"
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"))
        reader = admin.post(accounts, json={"name": "reader", "role": "viewer"}).json()
        writer = admin.post(accounts, json={"name": "writer", "role": "editor"}).json()
        assert_problem(admin.post(accounts, json={"name": "boss", "role": "owner"}), 422)
        listed = admin.get(accounts).json()["service_accounts"]
        assert sorted((a["name"], a["role"]) for a in listed) == [
            ("reader", "viewer"),
            ("writer", "editor"),
        ]
        assert all("token" not in a for a in listed)
    _, viewer = user_with_role(server, slug, "viewer")
    with server.client(viewer) as c:
        assert_problem(c.get(accounts), 403)
    with server.client(reader["token"]) as c:
        assert echoed(c.get(path(slug, "echo", "echo/r")))["method"] == "GET"
        gateway_problem(c.post(path(slug, "echo", "echo/r")), 403)
        gateway_problem(c.get(path(DEFAULT_TWIN, "echo", "echo/r")), 403)  # its twin only
    with server.client(writer["token"]) as c:
        assert echoed(c.post(path(slug, "echo", "echo/w"), content=b"1"))["body_len"] == 1
    with server.admin as admin:
        assert admin.delete(f"{accounts}/reader").status_code == 204
    with server.client(reader["token"]) as c:
        gateway_problem(c.get(path(slug, "echo", "echo/r")), 401)


def test_the_audit_log_records_every_answer(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    owner_name, owner = user_with_role(server, slug, "owner")
    viewer_name, viewer = user_with_role(server, slug, "viewer")
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"), methods=["GET", "POST"])
    with server.client(viewer) as c:
        c.get(path(slug, "echo", "echo/one"))
        c.post(path(slug, "echo", "echo/two"))
    with server.client(owner) as c:
        c.put(path(slug, "echo", "echo/three"))
        c.post(path(slug, "echo", "echo/four"), content=b"12345")
        r = c.get("/api/v1/gateway/audit", params={"twin": slug})
    assert r.status_code == 200, r.text
    got = [
        (e["caller"], e["method"], e["path"], e["status"], e["outcome"])
        for e in r.json()["entries"]
    ]
    assert got == [
        (owner_name, "POST", "/echo/four", 200, "forwarded"),
        (owner_name, "PUT", "/echo/three", 405, "refused"),
        (viewer_name, "POST", "/echo/two", 403, "refused"),
        (viewer_name, "GET", "/echo/one", 200, "forwarded"),
    ]
    newest = r.json()["entries"][0]
    assert (newest["twin"], newest["service"], newest["bytes_in"]) == (slug, "echo", 5)
    assert newest["bytes_out"] > 0 and newest["upstream_ms"] is not None
    with server.client(viewer) as c:
        assert_problem(c.get("/api/v1/gateway/audit", params={"twin": slug}), 403)
        assert_problem(c.get("/api/v1/gateway/audit"), 403)
    with server.client(owner) as c:
        assert_problem(c.get("/api/v1/gateway/audit"), 403)  # the whole log is for admins
    with server.admin as admin:
        mine: dict[str, str | int] = {"twin": slug, "user": viewer_name, "status": 403}
        entries = admin.get("/api/v1/gateway/audit", params=mine).json()["entries"]
        assert [(e["method"], e["path"]) for e in entries] == [("POST", "/echo/two")]
        page = admin.get("/api/v1/gateway/audit", params={"twin": slug, "limit": 3}).json()
        rest = admin.get(
            "/api/v1/gateway/audit",
            params={"twin": slug, "limit": 3, "before": page["next_before"]},
        ).json()
        assert [e["path"] for e in page["entries"] + rest["entries"]] == [
            "/echo/four", "/echo/three", "/echo/two", "/echo/one",
        ]  # fmt: skip
        everyone = admin.get("/api/v1/gateway/audit", params={"limit": 1000}).json()["entries"]
        assert {e["twin"] for e in everyone} > {slug}


def test_audit_times_ids_and_statuses_have_a_range(server: Server, upstream: Upstream) -> None:
    # Issue 13, item 2: each of these was a 500 (an int64 overflow in SQLite, or int(nan)).
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"))
        admin.get(path(slug, "echo", "echo/timed"))
        audit = "/api/v1/gateway/audit"
        for name, value in [
            ("since", "1e10"), ("until", "1e10"), ("since", "nan"), ("until", "inf"),
            ("since", "-1"), ("before", "9223372036854775808"), ("before", "0"),
            ("status", "9223372036854775808"), ("status", "99"), ("limit", "1e400"),
        ]:  # fmt: skip
            detail = assert_problem(admin.get(audit, params={name: value}), 422)["detail"]
            assert f"query.{name}" in detail, detail
        # In range, they still select: the entry is between 2000 and the last second of 2262.
        found = admin.get(audit, params={"twin": slug, "since": 946684800, "until": 9223372036})
        assert [e["path"] for e in found.json()["entries"]] == ["/echo/timed"], found.text
        later = admin.get(audit, params={"twin": slug, "since": time.time() + 3600})
        assert later.json()["entries"] == []
        assert admin.get(audit, params={"before": 2**63 - 1}).status_code == 200


def test_metrics_count_the_requests_of_each_service(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"), methods=["GET"])
        for _ in range(3):
            admin.get(path(slug, "echo", "echo/m"))
        admin.post(path(slug, "echo", "echo/m"))
        text = admin.get("/metrics").text
    assert sample(text, "twinlink_gateway_requests_total", slug, status="200") == 3
    assert sample(text, "twinlink_gateway_requests_total", slug, status="405") == 1
    assert sample(text, "twinlink_gateway_upstream_seconds_count", slug) == 3
    # The service's view has the same figures for the web app's monitor.
    with server.admin as admin:
        stats = admin.get(f"/api/v1/twins/{slug}/services/echo").json()["stats"]
    assert stats["statuses"] == {"200": 3, "405": 1}
    ms = stats["upstream_ms"]
    assert ms["mean"] > 0 and ms["p50"] is not None and ms["p50"] <= ms["p95"]
    assert stats["bytes_out"] > 0


def sample(text: str, name: str, slug: str, **labels: str) -> float:
    wanted = {"twin": slug, "service": "echo", **labels}
    [value] = [
        s.value
        for family in text_string_to_metric_families(text)
        for s in family.samples
        if s.name == name and s.labels == wanted
    ]
    return float(value)
