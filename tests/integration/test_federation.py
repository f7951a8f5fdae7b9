"""Relations across instances (issue 18, docs/federation.md): three twinlink servers on
loopback (allowed explicitly) that link to each other, a cycle between two of them, a dead
link, a slow instance (a TCP server that accepts and never answers), a redirect loop and an
oversized document. Nothing hangs (every answer comes within the client's timeout) and
nothing leaks (the slow instance's connections are closed, no unhandled error is logged)."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import (
    YAML_HEADERS,
    assert_problem,
    make_user,
    poll_until,
    twin_doc,
    unhandled_errors,
)

pytestmark = pytest.mark.integration

ENV = {
    "TWINLINK_FEDERATION_ALLOW_PRIVATE": "true",  # the instances are all on loopback
    "TWINLINK_FEDERATION_HOSTS": "127.0.0.1",
    "TWINLINK_FEDERATION_TIMEOUT_S": "2",
    "TWINLINK_FEDERATION_MAX_HOPS": "3",
    "TWINLINK_FEDERATION_MAX_KB": "64",
    "TWINLINK_FEDERATION_STALE_S": "3600",
}


@dataclass
class Odd:
    """Instances that misbehave, served by one asyncio loop in a thread."""

    loop: asyncio.AbstractEventLoop
    slow_port: int = 0
    loop_port: int = 0
    big_port: int = 0
    open_slow: set[asyncio.StreamWriter] = field(default_factory=set)
    slow_seen: int = 0

    @property
    def slow_url(self) -> str:
        return f"http://127.0.0.1:{self.slow_port}/twins/slow"

    @property
    def loop_url(self) -> str:
        return f"http://127.0.0.1:{self.loop_port}/twins/a"

    @property
    def big_url(self) -> str:
        return f"http://127.0.0.1:{self.big_port}/twins/big"


async def _serve(odd: Odd) -> list[asyncio.Server]:
    async def slow(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        # Accepts, reads the request, never answers: until the other side hangs up.
        odd.open_slow.add(writer)
        odd.slow_seen += 1
        try:
            while await reader.read(1024):
                pass
        finally:
            odd.open_slow.discard(writer)
            writer.close()

    async def redirects(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        head = await reader.readuntil(b"\r\n\r\n")
        path = head.split(b" ", 2)[1]
        to = b"/twins/b" if path == b"/twins/a" else b"/twins/a"
        writer.write(b"HTTP/1.1 302 Found\r\nLocation: " + to + b"\r\nContent-Length: 0\r\n\r\n")
        await writer.drain()
        writer.close()

    async def big(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.readuntil(b"\r\n\r\n")
        # No Content-Length: the size is only known by reading, which stops at the limit.
        writer.write(b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\n\r\n")
        writer.write(b'{"name": "big", "pad": "')
        try:
            for _ in range(1024):  # 1 MB more, if the client keeps reading
                writer.write(b"x" * 1024)
                await writer.drain()
            writer.write(b'"}')
        except ConnectionError:
            pass
        writer.close()

    servers = [await asyncio.start_server(h, "127.0.0.1", 0) for h in (slow, redirects, big)]
    odd.slow_port, odd.loop_port, odd.big_port = (s.sockets[0].getsockname()[1] for s in servers)
    return servers


@pytest.fixture(scope="module")
def odd() -> Iterator[Odd]:
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    odd = Odd(loop)
    servers = asyncio.run_coroutine_threadsafe(_serve(odd), loop).result(10)
    try:
        yield odd
    finally:

        async def close() -> None:
            for w in list(odd.open_slow):
                w.close()
            for s in servers:
                s.close()
                await s.wait_closed()

        done: Future[None] = asyncio.run_coroutine_threadsafe(close(), loop)
        done.result(10)
        loop.call_soon_threadsafe(loop.stop)
        thread.join(10)
        loop.close()


@pytest.fixture(scope="module")
def instances(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Server, Server, Server]]:
    started: list[Server] = []
    try:
        for name in ("a", "b", "c"):
            started.append(start_server(tmp_path_factory.mktemp(name), ENV))
        yield started[0], started[1], started[2]
    finally:
        for s in started:
            stop_server(s)


def _put(server: Server, doc: str) -> None:
    with server.admin as c:
        r = c.post("/api/v1/apply", content=doc, headers=YAML_HEADERS)
    assert r.status_code == 200, r.text


def _twin(server: Server, slug: str, name: str, parent: str | None = None, **extra: Any) -> str:
    """A public twin whose id is its canonical URL there; returns that URL."""
    url = f"{server.url}/twins/{slug}"
    relations = [("parent", parent)] if parent else []
    _put(server, twin_doc(url, name=name, slug=slug, relations=relations, **extra))
    return url


def _up(server: Server, slug: str) -> dict[str, Any]:
    """The parent node of `slug` (relations up): a remote twin here."""
    with server.admin as c:
        r = c.get(f"/api/v1/twins/{slug}/relations", params={"direction": "up", "depth": 1})
    assert r.status_code == 200, r.text
    nodes = r.json()["nodes"]
    assert len(nodes) == 1, nodes
    return nodes[0]  # type: ignore[no-any-return]


def _state(server: Server, slug: str, state: str) -> dict[str, Any]:
    def check() -> dict[str, Any] | None:
        node = _up(server, slug)
        return node if node["remote"]["state"] == state else None

    return poll_until(check, f"{slug}'s parent {state}")  # type: ignore[no-any-return]


def test_twins_of_two_instances_link_to_each_other_in_a_cycle(
    instances: tuple[Server, Server, Server],
) -> None:
    a, b, _ = instances
    a_url, b_url = f"{a.url}/twins/pump", f"{b.url}/twins/plant"
    _twin(b, "plant", "Plant on B", parent=a_url)
    _twin(a, "pump", "Pump on A", parent=b_url)
    on_a = _state(a, "pump", "reachable")
    assert on_a["id"] == b_url and on_a["registered"] is False
    assert on_a["remote"]["name"] == "Plant on B"
    assert on_a["remote"]["url"] == b_url and on_a["remote"]["fetched_at"]
    on_b = _state(b, "plant", "reachable")
    assert on_b["remote"]["name"] == "Pump on A"
    # The remote twin is kept: listed, and resolvable on demand with its validators.
    with a.admin as c:
        r = c.get("/api/v1/resolve", params={"id": b_url})
    assert r.status_code == 200, r.text
    assert r.json()["remote"]["state"] == "reachable"


def test_search_includes_remote_twins_when_asked(instances: tuple[Server, Server, Server]) -> None:
    a, b, _ = instances
    b_url = _twin(b, "boiler", "Boiler on B")
    _twin(a, "burner", "Burner on A", parent=b_url)
    _state(a, "burner", "reachable")
    with a.admin as c:
        plain = c.get("/api/v1/search", params={"q": "boiler"}).json()
        asked = c.get("/api/v1/search", params={"q": "boiler", "remote": True}).json()
    assert "remote" not in plain or plain["remote"] is None
    assert [(h["name"], h["url"], h["state"]) for h in asked["remote"]] == [
        ("Boiler on B", b_url, "reachable")
    ]


def test_the_public_page_links_remote_relations(instances: tuple[Server, Server, Server]) -> None:
    a, b, _ = instances
    b_url = _twin(b, "line", "Line on B")
    _twin(a, "motor", "Motor on A", parent=b_url)
    _state(a, "motor", "reachable")
    with httpx.Client(base_url=a.url, timeout=30) as c:
        page = c.get("/twins/motor", headers={"Accept": "text/html"})
    assert page.status_code == 200
    assert f'href="{b_url}"' in page.text
    assert "Line on B" in page.text and "reachable" in page.text


def test_a_dead_link_is_gone(instances: tuple[Server, Server, Server]) -> None:
    a, _, c = instances
    dead = f"{c.url}/twins/never-there"
    _twin(a, "orphan", "Orphan", parent=dead)
    node = _state(a, "orphan", "gone")
    assert node["remote"]["fetched_at"] is None
    with a.admin as client:
        r = client.get("/api/v1/resolve", params={"id": dead})
    problem = assert_problem(r, 502)
    assert "404" in problem["detail"]


def test_a_copy_kept_turns_gone_when_its_twin_is_deleted(
    instances: tuple[Server, Server, Server],
) -> None:
    a, _, c = instances
    c_url = _twin(c, "valve", "Valve on C")
    _twin(a, "pipe", "Pipe on A", parent=c_url)
    _state(a, "pipe", "reachable")
    with c.admin as client:
        assert client.delete("/api/v1/twins/valve").status_code in (200, 204)
    with a.admin as client:
        assert_problem(client.get("/api/v1/resolve", params={"id": c_url}), 502)
    node = _up(a, "pipe")
    assert node["remote"]["state"] == "gone"
    assert node["remote"]["name"] == "Valve on C"  # the copy still says what it was


def test_a_slow_instance_neither_hangs_a_page_nor_leaks_a_connection(
    instances: tuple[Server, Server, Server], odd: Odd
) -> None:
    a, _, _ = instances
    _twin(a, "waiting", "Waiting", parent=odd.slow_url)
    # The page answers (within the client's 30 s timeout) while the fetch still waits.
    assert _up(a, "waiting")["remote"]["state"] in ("pending", "stale")
    node = _state(a, "waiting", "stale")
    assert node["remote"]["fetched_at"] is None
    with a.admin as c:
        problem = assert_problem(c.get("/api/v1/resolve", params={"id": odd.slow_url}), 502)
    assert "did not answer within 2 s" in problem["detail"]
    assert odd.slow_seen >= 2
    poll_until(lambda: not odd.open_slow, "the slow instance's connections closed")


def test_a_redirect_loop_is_refused_by_name(
    instances: tuple[Server, Server, Server], odd: Odd
) -> None:
    a, _, _ = instances
    _twin(a, "looped", "Looped", parent=odd.loop_url)
    _state(a, "looped", "stale")
    with a.admin as c:
        problem = assert_problem(c.get("/api/v1/resolve", params={"id": odd.loop_url}), 502)
    assert "redirect loop" in problem["detail"]
    assert f"{odd.loop_url} -> http://127.0.0.1:{odd.loop_port}/twins/b" in problem["detail"]


def test_an_oversized_document_is_not_read_past_the_limit(
    instances: tuple[Server, Server, Server], odd: Odd
) -> None:
    a, _, _ = instances
    with a.admin as c:
        problem = assert_problem(c.get("/api/v1/resolve", params={"id": odd.big_url}), 502)
    assert "larger than 65536 bytes" in problem["detail"]


def test_the_guard_refuses_what_the_settings_do_not_allow(
    instances: tuple[Server, Server, Server],
) -> None:
    a, b, _ = instances
    with a.admin as c:
        other_host = c.get(
            "/api/v1/resolve", params={"id": b.url.replace("127.0.0.1", "localhost")}
        )
        scheme = c.get("/api/v1/resolve", params={"id": "file:///etc/passwd"})
    assert "TWINLINK_FEDERATION_HOSTS" in assert_problem(other_host, 422)["detail"]
    assert "only http and https" in assert_problem(scheme, 422)["detail"]


def test_a_peers_token_shows_its_private_twins_and_is_never_shown(
    instances: tuple[Server, Server, Server],
) -> None:
    a, b, _ = instances
    secret_url = f"{b.url}/twins/secret-pump"
    _put(b, twin_doc(secret_url, name="Secret", slug="secret-pump",
                                    privacy="private"))  # fmt: skip
    with a.admin as c:
        hidden = c.get("/api/v1/resolve", params={"id": secret_url})
        assert_problem(hidden, 502)
        peer = b.url.removeprefix("http://")
        r = c.put(f"/api/v1/federation/peers/{peer}", json={"token": b.admin_token,
                                                            "scheme": "http"})  # fmt: skip
        assert r.status_code == 200, r.text
        assert r.json() == {"origin": b.url}
        listed = c.get("/api/v1/federation/peers")
        seen = c.get("/api/v1/resolve", params={"id": secret_url})
        assert seen.status_code == 200, seen.text
        assert seen.json()["remote"]["name"] == "Secret"
        assert c.delete(f"/api/v1/federation/peers/{peer}").status_code == 204
        assert_problem(c.delete(f"/api/v1/federation/peers/{peer}"), 404)
    assert listed.json() == {"peers": [b.url]}
    assert b.admin_token not in listed.text and b.admin_token not in a.log()
    stored = (a.data_dir / "federation-peers").read_bytes()
    assert b.admin_token.encode() not in stored


def test_peers_are_for_admins(instances: tuple[Server, Server, Server]) -> None:
    a, _, _ = instances
    token = make_user(a, "fed-viewer")
    with a.client(token) as c:
        assert_problem(c.get("/api/v1/federation/peers"), 403)
        assert_problem(c.put("/api/v1/federation/peers/x.org", json={"token": "t"}), 403)
        assert_problem(c.delete("/api/v1/federation/peers/x.org"), 403)


def test_nothing_went_wrong_inside(instances: tuple[Server, Server, Server]) -> None:
    for server in instances:
        assert unhandled_errors(server) == 0, server.log()[-3000:]
