"""What passes through the gateway and how: query strings, headers both ways, bodies far larger
than the server's memory streamed both ways, size limits, WebSockets, server-sent events,
timeouts, unreachable services, HEAD and redirects."""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import psutil
import pytest
from websockets.exceptions import ConnectionClosed, InvalidStatus
from websockets.sync.client import connect

from tests.conftest import Server, free_port
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._gateway import (
    add_service,
    echoed,
    header_names,
    new_twin,
    path,
    user_with_role,
    wait_until,
)
from tests.integration._gateway import server as server  # module fixture
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from tests.integration._upstream_answers import CHUNK, block, download_digest
from tests.integration._util import assert_problem, unique

pytestmark = pytest.mark.integration
MIB = 1 << 20
RSS_BOUND = 64 * MIB


@pytest.fixture(scope="module")
def twin(server: Server, upstream: Upstream) -> str:
    """A twin with service `echo` on the upstream's open realm, taking bodies up to 300 MB."""
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "echo", upstream.base("open"), limits={"max_body_mb": 300})
    return slug


@contextmanager
def peak_rss_growth(server: Server) -> Iterator[list[int]]:
    """Samples the server process's RSS while the block runs; yields [peak growth] after."""
    process = psutil.Process(server.process.pid)
    start = process.memory_info().rss
    peak, done = [start], threading.Event()

    def sample() -> None:
        while not done.wait(0.01):
            peak[0] = max(peak[0], process.memory_info().rss)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    growth = [0]
    try:
        yield growth
    finally:
        done.set()
        sampler.join()
        growth[0] = max(peak[0], process.memory_info().rss) - start


def test_the_query_string_is_kept_as_sent(server: Server, twin: str) -> None:
    query = "a=1&b=%20c%2Fd&a=2&empty=&flag&utf=%C3%A4"
    with server.admin as admin:
        answer = echoed(admin.get(path(twin, "echo", f"echo/q?{query}")))
    assert answer["query"] == query


def test_hop_by_hop_and_forwarding_headers(server: Server, twin: str) -> None:
    sent = {
        "Connection": "keep-alive, X-Private",
        "X-Private": "for the next hop only",
        "Keep-Alive": "timeout=5",
        "TE": "trailers",
        "Proxy-Authorization": "Basic Zm9vOmJhcg==",
        "Cookie": "twinlink_session=platform-cookie",
        "X-Forwarded-For": "6.6.6.6",
        "X-Forwarded-Host": "forged.example",
        "X-Forwarded-Proto": "https",
        "X-Forwarded-Prefix": "/forged",
        "Forwarded": "for=6.6.6.6",
        "X-Real-IP": "6.6.6.6",
        "X-End-To-End": "kept",
    }
    with server.admin as admin:
        answer = echoed(admin.get(path(twin, "echo", "echo/h"), headers=sent))
        hop = admin.get(path(twin, "echo", "hop"))
        cookie = admin.get(path(twin, "echo", "cookie"))
    names = header_names(answer)
    for gone in ("x-private", "keep-alive", "te", "proxy-authorization", "cookie", "forwarded",
                 "x-real-ip", "authorization"):  # fmt: skip
        assert gone not in names, gone
    got = {k: [v for n, v in answer["headers"] if n == k] for k in names}
    host = server.url.removeprefix("http://")
    assert got["x-forwarded-for"] == ["127.0.0.1"]  # the client's own claim is not trusted
    assert got["x-forwarded-host"] == [host]
    assert got["x-forwarded-proto"] == ["http"]
    assert got["x-forwarded-prefix"] == [f"/twins/{twin}/services/echo"]
    assert got["x-end-to-end"] == ["kept"]
    # The answer: hop-by-hop headers and the service's cookies stay behind.
    assert hop.status_code == 200 and hop.headers["x-end-to-end"] == "kept"
    assert "x-hop-private" not in hop.headers and "keep-alive" not in hop.headers
    assert cookie.status_code == 200 and "set-cookie" not in cookie.headers


def test_a_download_larger_than_memory_streams(server: Server, twin: str) -> None:
    size = 512 * MIB + 12345
    digest, received = hashlib.sha256(), 0
    target = path(twin, "echo", f"bytes/{size}")
    with server.admin as admin:  # warm up: the allocator's first growth does not scale
        assert len(admin.get(path(twin, "echo", f"bytes/{32 * MIB}")).content) == 32 * MIB
    with (
        server.admin as admin,
        peak_rss_growth(server) as growth,
        admin.stream("GET", target) as r,
    ):
        assert r.status_code == 200 and r.headers["content-length"] == str(size)
        for chunk in r.iter_raw():
            digest.update(chunk)
            received += len(chunk)
    assert received == size
    assert digest.hexdigest() == download_digest(size)
    assert growth[0] < RSS_BOUND, f"the server grew by {growth[0] / MIB:.0f} MiB"


def test_a_download_stops_when_the_client_leaves(server: Server, twin: str) -> None:
    size = 512 * MIB
    target = path(twin, "echo", f"bytes/{size}")
    with server.admin as admin:
        with admin.stream("GET", target) as r:
            assert len(next(r.iter_raw())) > 0

        # The server writes the entry once it has noticed; ask until it is there.
        def entry() -> dict[str, Any] | None:
            params: dict[str, str | int] = {"twin": twin, "limit": 10}
            found = admin.get("/api/v1/gateway/audit", params=params).json()["entries"]
            return next((e for e in found if e["path"] == f"/bytes/{size}"), None)

        left = wait_until(entry, what="the audit entry of the abandoned download")
    assert (left["status"], left["outcome"]) == (499, "client_left")
    assert left["bytes_out"] < 64 * MIB


def test_a_download_of_unknown_length_streams(server: Server, twin: str) -> None:
    size = 8 * MIB + 1
    with server.admin as admin:
        r = admin.get(path(twin, "echo", f"bytes/{size}?chunked=1"))
    assert "content-length" not in r.headers
    assert hashlib.sha256(r.content).hexdigest() == download_digest(size)


def test_an_upload_larger_than_memory_streams(server: Server, twin: str) -> None:
    size = 256 * MIB

    def body() -> Iterator[bytes]:
        yield from (block(i) for i in range(size // CHUNK))

    headers = {"Content-Length": str(size)}
    with server.admin as admin, peak_rss_growth(server) as growth:
        r = admin.post(path(twin, "echo", "echo/upload"), content=body(), headers=headers)
    answer = echoed(r)
    assert (answer["body_len"], answer["body_sha256"]) == (size, download_digest(size))
    assert growth[0] < RSS_BOUND, f"the server grew by {growth[0] / MIB:.0f} MiB"


def test_an_upload_of_unknown_length_streams(server: Server, twin: str) -> None:
    size = 5 * MIB + 7
    data = b"".join(block(i) for i in range(6))[:size]

    def body() -> Iterator[bytes]:
        yield from (data[i : i + 100_000] for i in range(0, size, 100_000))

    with server.admin as admin:
        answer = echoed(admin.put(path(twin, "echo", "echo/chunked"), content=body()))
    assert (answer["body_len"], answer["body_sha256"]) == (size, hashlib.sha256(data).hexdigest())
    assert "chunked" in [v for k, v in answer["headers"] if k == "transfer-encoding"]


def test_bodies_over_the_limit_are_refused(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    marker = unique("limit")
    with server.admin as admin:
        add_service(admin, slug, "small", upstream.base("open"), limits={"max_body_mb": 1})
        declared = admin.post(path(slug, "small", f"echo/{marker}"), content=b"z" * (2 * MIB))
        streamed = admin.post(
            path(slug, "small", f"echo/{marker}"), content=iter([b"z" * MIB, b"z" * MIB])
        )
        ok = admin.post(path(slug, "small", "echo/ok"), content=b"z" * MIB)
    assert_problem(declared, 413)
    assert_problem(streamed, 413)
    assert upstream.requests_to(marker) == []  # refused before anything was forwarded
    assert echoed(ok)["body_len"] == MIB


def ws_url(server: Server, target: str) -> str:
    return server.url.replace("http://", "ws://") + target


def test_websocket_frames_and_close_codes_pass_through(
    server: Server, upstream: Upstream, twin: str
) -> None:
    _, editor = user_with_role(server, twin, "editor")
    headers = {"Authorization": f"Bearer {editor}"}
    with connect(ws_url(server, path(twin, "echo", "ws")), additional_headers=headers) as ws:
        ws.send("text frame")
        assert ws.recv(timeout=10) == "text frame"
        ws.send(b"\x00\x01binary")
        assert ws.recv(timeout=10) == b"\x00\x01binary"
        ws.send("close:4001:service says bye")
        with pytest.raises(ConnectionClosed) as closed:
            ws.recv(timeout=10)
    assert closed.value.rcvd is not None
    assert (closed.value.rcvd.code, closed.value.rcvd.reason) == (4001, "service says bye")
    closes = len(upstream.ws_closes)
    with connect(ws_url(server, path(twin, "echo", "ws")), additional_headers=headers) as ws:
        ws.send("ping")
        assert ws.recv(timeout=10) == "ping"
        ws.close(4002, "client says bye")
    got = wait_until(lambda: upstream.ws_closes[closes:] or None, what="the upstream's close")
    assert got == [4002]


def test_websockets_need_the_editor_role_and_take_a_query_token(
    server: Server, upstream: Upstream, twin: str
) -> None:
    _, viewer = user_with_role(server, twin, "viewer")
    _, editor = user_with_role(server, twin, "editor")
    with pytest.raises(InvalidStatus) as refused:
        connect(
            ws_url(server, path(twin, "echo", "ws")),
            additional_headers={"Authorization": f"Bearer {viewer}"},
        ).close()
    assert refused.value.response.status_code == 403
    with pytest.raises(InvalidStatus) as anonymous:
        connect(ws_url(server, path(twin, "echo", "ws"))).close()
    assert anonymous.value.response.status_code == 401
    marker = unique("wsq")
    target = path(twin, "echo", f"ws?a={marker}&access_token={editor}&b=2")
    with connect(ws_url(server, target)) as ws:
        ws.send("via query")
        assert ws.recv(timeout=10) == "via query"
    [seen] = upstream.requests_to(marker)
    assert seen.query == f"a={marker}&b=2"  # the platform token is not passed on
    assert editor not in str(seen.headers) and not seen.header("authorization")


def test_a_service_without_websockets_refuses_them(server: Server, upstream: Upstream) -> None:
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "plain", upstream.base("open"), websocket=False)
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    with pytest.raises(InvalidStatus) as refused:
        connect(ws_url(server, path(slug, "plain", "ws")), additional_headers=headers).close()
    assert refused.value.response.status_code == 403


def test_server_sent_events_arrive_as_they_are_sent(
    server: Server, upstream: Upstream, twin: str
) -> None:
    key = unique("sse")
    with (
        server.admin as admin,
        admin.stream("GET", path(twin, "echo", f"sse/{key}"), timeout=10) as r,
    ):
        assert r.headers["content-type"] == "text/event-stream"
        lines = r.iter_lines()
        # The upstream sends its last event only once this one has been read here.
        assert next(lines) == "data: first"
        upstream.release(key)
        rest = [line for line in lines if line]
    assert rest == ["data: last"]


def test_a_slow_service_is_a_504_and_an_absent_one_a_502(
    server: Server, upstream: Upstream
) -> None:
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "slow", upstream.base("open"), limits={"timeout_s": 0.3})
        add_service(admin, slug, "gone", f"http://127.0.0.1:{free_port()}/")
        slow = assert_problem(admin.get(path(slug, "slow", "slow")), 504)
        gone = assert_problem(admin.get(path(slug, "gone", "x")), 502)
    assert (slow["code"], slow["source"]) == ("timeout", "gateway")
    assert (gone["code"], gone["source"]) == ("upstream_connect", "gateway")


def test_head_answers_have_no_body_and_keep_the_connection_usable(
    server: Server, twin: str
) -> None:
    with server.admin as admin:
        for _ in range(3):
            r = admin.head(path(twin, "echo", f"bytes/{5 * MIB}"))
            assert (r.status_code, r.headers["content-length"], r.content) == (
                200,
                str(5 * MIB),
                b"",
            )
            small = admin.get(path(twin, "echo", "bytes/100"))
            assert small.content == block(0)[:100]


def test_redirects_inside_the_service_are_rewritten(server: Server, twin: str) -> None:
    prefix = f"/twins/{twin}/services/echo"
    with server.admin as admin:
        locations = {
            how: admin.get(path(twin, "echo", f"redirect/{how}"))
            for how in (
                "inside-absolute",
                "inside-path",
                "relative",
                "outside-host",
                "outside-path",
            )
        }
    assert locations["inside-absolute"].headers["location"] == f"{prefix}/echo/landed?x=1"
    assert locations["inside-path"].headers["location"] == f"{prefix}/echo/landed"
    assert locations["relative"].headers["location"] == "echo/landed"
    for how in ("outside-host", "outside-path"):
        problem = assert_problem(locations[how], 502)
        assert problem["code"] == "redirect_refused"
