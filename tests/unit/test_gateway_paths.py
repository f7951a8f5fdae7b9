"""Which paths reach the gateway, and which stay below a service's base URL."""

from __future__ import annotations

import pytest

from twinlink.gateway import paths
from twinlink.gateway.headers import RedirectRefused, request_headers, response_headers


def test_twin_and_default_routes() -> None:
    route = paths.match(b"/twins/crane/services/historian/api/v1/x")
    assert route == paths.Route(
        "crane", "historian", b"api/v1/x", "/twins/crane/services/historian"
    )
    assert paths.match(b"/twins/crane/services/historian") is not None
    default = paths.match(b"/services/cad-store/files/a.stl")
    assert default is not None and default.twin is None and default.rest == b"files/a.stl"
    assert paths.match(b"/twins/crane") is None
    assert paths.match(b"/api/v1/twins/crane/services") is None


@pytest.mark.parametrize(
    "rest",
    [
        b"..",
        b"a/../../etc/passwd",
        b"%2e%2e/x",
        b"%2E%2e/x",
        b".%2e/x",
        b"a%2f..%2fb",
        b"a%5cb",
        b"a%00b",
        b"%252e%252e/x",
        b"/evil.example/x",
        b"http:%2f%2fevil/x",
        b"http://evil.example/x",
        b"a/./b",
        b"a b",
    ],
)
def test_paths_that_could_leave_the_service_are_refused(rest: bytes) -> None:
    with pytest.raises(paths.PathRefused):
        paths.check_rest(rest)


@pytest.mark.parametrize("rest", [b"", b"files/a.stl", b"a/b%20c/d", b"x:y@z", b"%7Euser/..a"])
def test_ordinary_paths_pass_unchanged(rest: bytes) -> None:
    assert paths.check_rest(rest) == rest


def test_target_keeps_the_query_and_adds_credentials_last() -> None:
    assert paths.target("/api/", b"x", b"a=1&b=2", ["key=s"]) == "/api/x?a=1&b=2&key=s"
    assert paths.target("/", b"", b"", []) == "/"


def test_the_websocket_token_is_taken_out_of_the_query() -> None:
    query, token = paths.strip_query_param(b"a=1&access_token=tl_x%2By&b=2", b"access_token")
    assert (query, token) == (b"a=1&b=2", "tl_x+y")


def test_request_headers_drop_hop_by_hop_and_the_clients_credentials() -> None:
    sent = [
        (b"host", b"gw:8000"),
        (b"authorization", b"Bearer tl_secret"),
        (b"cookie", b"session=1"),
        (b"connection", b"keep-alive, x-private"),
        (b"x-private", b"1"),
        (b"te", b"trailers"),
        (b"x-forwarded-for", b"6.6.6.6"),
        (b"accept", b"application/json"),
    ]
    out = dict(
        request_headers(sent, b"svc:80", "10.0.0.1", "http", b"gw:8000", "/twins/t/services/s")
    )
    assert out[b"host"] == b"svc:80"
    assert out[b"x-forwarded-for"] == b"10.0.0.1"
    assert out[b"x-forwarded-prefix"] == b"/twins/t/services/s"
    assert out[b"accept"] == b"application/json"
    for gone in (b"authorization", b"cookie", b"connection", b"x-private", b"te"):
        assert gone not in out


def test_redirects_inside_the_service_become_gateway_paths() -> None:
    prefix = "/twins/t/services/s"
    base = "http://svc:8080/api/"
    got = dict(response_headers([(b"Location", b"http://svc:8080/api/x?y=1")], base, prefix))
    assert got[b"location"] == b"/twins/t/services/s/x?y=1"
    got = dict(response_headers([(b"location", b"/api/login")], base, prefix))
    assert got[b"location"] == b"/twins/t/services/s/login"
    got = dict(response_headers([(b"location", b"next")], base, prefix))
    assert got[b"location"] == b"next"
    for outside in (
        b"http://evil.example/api/x",
        b"//evil.example/x",
        b"/admin",
        b"http://svc:8080/api/../admin",
        b"../../x",
        b"a/%2e%2e/%2e%2e/b",
    ):
        with pytest.raises(RedirectRefused):
            response_headers([(b"location", outside)], base, prefix)


def test_the_services_cookies_are_not_passed_back() -> None:
    got = dict(response_headers([(b"set-cookie", b"a=1"), (b"etag", b"x")], "http://s/", "/p"))
    assert got == {b"etag": b"x"}
