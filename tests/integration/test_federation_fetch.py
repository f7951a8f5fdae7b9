"""The Fetcher (federation/fetch.py) against real HTTP servers on loopback sockets: redirects
followed hop by hop through the guard, a peer's token sent to its own origin only, validators,
Twinbase's folders, and the limits (hops, size, compressed size, one deadline for the whole
fetch, even against a server that keeps sending a byte at a time)."""

from __future__ import annotations

import asyncio
import gzip
import json
import re
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

import pytest

from twinlink.federation.fetch import Fetcher, FetchFailed, FetchPolicy, FetchRefused

pytestmark = pytest.mark.integration

LOOPBACK = FetchPolicy(hosts=("127.0.0.1",), allow_private=True, max_hops=3, timeout_s=5)


@dataclass
class Request:
    path: str
    headers: dict[str, str]
    writer: asyncio.StreamWriter  # for answers that write as they go


Answer = Callable[[Request], Awaitable[bytes]]


@dataclass
class Site:
    """A tiny HTTP/1.1 server: one request a connection, answered by `answer`."""

    answer: Answer
    port: int = 0
    seen: list[Request] = field(default_factory=list)
    server: asyncio.Server | None = None

    @property
    def origin(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            head = (await reader.readuntil(b"\r\n\r\n")).decode("latin-1").split("\r\n")
            headers = {
                k.lower(): v.strip() for k, _, v in (h.partition(":") for h in head[1:] if h)
            }
            request = Request(head[0].split(" ")[1], headers, writer)
            self.seen.append(request)
            writer.write(await self.answer(request))
            await writer.drain()
        except (ConnectionError, asyncio.IncompleteReadError):
            pass
        finally:
            writer.close()


@pytest.fixture
async def sites() -> AsyncIterator[Callable[[Answer], Awaitable[Site]]]:
    started: list[Site] = []

    async def start(answer: Answer) -> Site:
        site = Site(answer)
        site.server = await asyncio.start_server(site._handle, "127.0.0.1", 0)
        site.port = site.server.sockets[0].getsockname()[1]
        started.append(site)
        return site

    yield start
    for site in started:
        assert site.server is not None
        site.server.close()
        await site.server.wait_closed()


def ok(body: bytes, content_type: str = "application/json", extra: str = "") -> bytes:
    return (
        f"HTTP/1.1 200 OK\r\nContent-Type: {content_type}\r\nContent-Length: {len(body)}\r\n"
        f"{extra}Connection: close\r\n\r\n"
    ).encode() + body


def redirect(location: str, status: int = 302) -> bytes:
    return (
        f"HTTP/1.1 {status} Moved\r\nLocation: {location}\r\nContent-Length: 0\r\n"
        "Connection: close\r\n\r\n"
    ).encode()


DOC = {"dt-id": "http://example.org/twins/a", "name": "Pump", "relations": []}


async def test_a_peers_token_goes_to_its_origin_and_never_across_a_redirect(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    async def document(_r: Request) -> bytes:
        return ok(json.dumps(DOC).encode())

    elsewhere = await sites(document)

    async def peer_answer(r: Request) -> bytes:
        return redirect(f"{elsewhere.origin}/twins/a") if r.path == "/away" else ok(b'{"a": 1}')

    peer = await sites(peer_answer)
    tokens = {peer.origin: "peer-secret"}
    fetcher = Fetcher(LOOPBACK, tokens.get)
    try:
        got = await fetcher.fetch_document(f"{peer.origin}/away")
    finally:
        await fetcher.aclose()
    assert got.document == DOC and got.url == f"{elsewhere.origin}/twins/a"
    assert peer.seen[0].headers["authorization"] == "Bearer peer-secret"
    assert "authorization" not in elsewhere.seen[0].headers
    assert "cookie" not in elsewhere.seen[0].headers


async def test_validators_are_sent_and_an_unchanged_document_costs_a_304(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    async def answer(r: Request) -> bytes:
        if r.headers.get("if-none-match") == '"v1"':
            return b'HTTP/1.1 304 Not Modified\r\nETag: "v1"\r\nConnection: close\r\n\r\n'
        last = "Last-Modified: Wed, 21 Oct 2026 07:28:00 GMT\r\n"
        return ok(json.dumps(DOC).encode(), extra=f'ETag: "v1"\r\n{last}')

    site = await sites(answer)
    fetcher = Fetcher(LOOPBACK)
    try:
        first = await fetcher.fetch_document(f"{site.origin}/twins/a")
        again = await fetcher.fetch_document(
            f"{site.origin}/twins/a", etag=first.etag, last_modified=first.last_modified
        )
    finally:
        await fetcher.aclose()
    assert (first.etag, first.last_modified) == ('"v1"', "Wed, 21 Oct 2026 07:28:00 GMT")
    assert again.not_modified and again.document is None and again.status == 304
    assert site.seen[1].headers["if-modified-since"] == "Wed, 21 Oct 2026 07:28:00 GMT"


async def test_a_dt_id_answering_html_leads_to_its_folders_index_json(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    yaml_doc = b"dt-id: http://example.org/twins/b\nname: Valve\n"

    async def answer(r: Request) -> bytes:
        if r.path == "/dtid/b":  # a dt-id service: redirects to the hosting-iri
            return redirect("/site/b/", 303)
        if r.path == "/site/b/":  # Twinbase's page of the twin
            return ok(b"<html>Valve</html>", "text/html; charset=utf-8")
        if r.path == "/site/b/index.json":
            return ok(json.dumps({"dt-id": "http://example.org/twins/b", "name": "Valve"}).encode())
        return ok(yaml_doc, "application/yaml")

    site = await sites(answer)
    fetcher = Fetcher(LOOPBACK)
    try:
        folder = await fetcher.fetch_document(f"{site.origin}/dtid/b")
        plain_yaml = await fetcher.fetch_document(f"{site.origin}/b.yaml")
    finally:
        await fetcher.aclose()
    assert folder.url == f"{site.origin}/site/b/index.json"
    assert folder.document == {"dt-id": "http://example.org/twins/b", "name": "Valve"}
    assert plain_yaml.document == {"dt-id": "http://example.org/twins/b", "name": "Valve"}
    assert "application/json" in site.seen[0].headers["accept"]


async def test_redirects_past_max_hops_and_loops_are_refused(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    async def answer(r: Request) -> bytes:
        if r.path == "/loop":
            return redirect("/loop#again")  # the fragment does not hide the loop
        n = int(r.path.strip("/"))
        return redirect(f"/{n + 1}")

    site = await sites(answer)
    fetcher = Fetcher(LOOPBACK)
    try:
        with pytest.raises(FetchFailed, match=r"more than 3 redirects") as hops:
            await fetcher.fetch_document(f"{site.origin}/1")
        with pytest.raises(FetchFailed, match="a redirect loop") as loop:
            await fetcher.fetch_document(f"{site.origin}/loop")
    finally:
        await fetcher.aclose()
    assert f"{site.origin}/4 -> {site.origin}/5" in str(hops.value)
    assert len(site.seen) == 4 + 1  # /1 to /4, then /loop once: nothing fetched past the limit
    assert f"{site.origin}/loop -> {site.origin}/loop" in str(loop.value)


async def test_every_redirect_hop_is_checked_by_the_guard(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    async def answer(r: Request) -> bytes:
        targets = {
            "/meta": "http://169.254.169.254/latest/meta-data/",
            "/name": f"http://localhost:{site.port}/x",  # not in the allowed hosts
            "/file": "file:///etc/passwd",
        }
        return redirect(targets[r.path])

    site = await sites(answer)
    public_only = FetchPolicy(hosts=("*",), allow_private=False)
    fetcher = Fetcher(LOOPBACK)
    strict = Fetcher(public_only)
    try:
        with pytest.raises(FetchRefused, match="the host localhost is not in"):
            await fetcher.fetch_document(f"{site.origin}/name")
        with pytest.raises(FetchRefused, match="only http and https"):
            await fetcher.fetch_document(f"{site.origin}/file")
        with pytest.raises(FetchRefused, match=re.escape("the host 169.254.169.254 is not in")):
            await fetcher.fetch_document(f"{site.origin}/meta")
        with pytest.raises(FetchRefused, match="a loopback address"):  # the first hop already
            await strict.fetch_document(f"{site.origin}/meta")
    finally:
        await fetcher.aclose()
        await strict.aclose()
    assert [r.path for r in site.seen] == ["/name", "/file", "/meta"]


async def test_a_document_is_not_read_past_the_limit(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    big = json.dumps({"name": "x" * 5000}).encode()
    bomb = gzip.compress(json.dumps({"name": "y" * 200_000}).encode())

    async def answer(r: Request) -> bytes:
        if r.path == "/declared":
            return ok(big)
        if r.path == "/gzip":
            return ok(bomb, extra="Content-Encoding: gzip\r\n")
        head = b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nConnection: close\r\n\r\n"
        return head + big  # no Content-Length: the limit is found by reading

    site = await sites(answer)
    small = FetchPolicy(hosts=("127.0.0.1",), allow_private=True, max_bytes=4096)
    fetcher = Fetcher(small)
    try:
        for path in ("/declared", "/streamed", "/gzip"):
            with pytest.raises(FetchFailed, match="larger than 4096 bytes"):
                await fetcher.fetch_document(f"{site.origin}{path}")
    finally:
        await fetcher.aclose()
    assert len(bomb) < 4096  # small on the wire, refused for what it unpacks to


async def test_one_deadline_covers_the_whole_fetch_even_a_byte_a_tick(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    release = asyncio.Event()

    async def answer(r: Request) -> bytes:
        # Never finishes on its own: a byte every 50 ms keeps any per-read timeout happy.
        r.writer.write(b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\n\r\n{")
        while not release.is_set():
            r.writer.write(b" ")
            await r.writer.drain()
            await asyncio.sleep(0.05)
        return b""

    site = await sites(answer)
    quick = FetchPolicy(hosts=("127.0.0.1",), allow_private=True, timeout_s=0.5)
    fetcher = Fetcher(quick)
    try:
        with pytest.raises(FetchFailed, match=re.escape("did not answer within 0.5 s")):
            await fetcher.fetch_document(f"{site.origin}/slow")
    finally:
        release.set()
        await fetcher.aclose()
    assert [r.path for r in site.seen] == ["/slow"]


async def test_what_is_not_one_document_is_refused(
    sites: Callable[[Answer], Awaitable[Site]],
) -> None:
    answers = {
        "/list": ok(b"[1, 2]"),
        "/broken": ok(b'{"name": '),
        "/two": ok(b"name: a\n---\nname: b\n", "application/yaml"),
        "/gone": b"HTTP/1.1 410 Gone\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
        "/error": b"HTTP/1.1 500 Oops\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
    }

    async def answer(r: Request) -> bytes:
        return answers[r.path]

    site = await sites(answer)
    fetcher = Fetcher(LOOPBACK)
    failures: dict[str, Any] = {}
    try:
        for path in answers:
            with pytest.raises(FetchFailed) as err:
                await fetcher.fetch_document(f"{site.origin}{path}")
            failures[path] = err.value
    finally:
        await fetcher.aclose()
    assert "not a DT document" in str(failures["/list"])
    assert "not a DT document" in str(failures["/broken"])
    assert "not a DT document" in str(failures["/two"])
    assert failures["/gone"].remote_status == 410 and failures["/error"].remote_status == 500


async def test_the_connection_goes_to_the_checked_address_with_the_name_as_host(
    sites: Callable[[Answer], Awaitable[Site]], monkeypatch: pytest.MonkeyPatch
) -> None:
    async def answer(_r: Request) -> bytes:
        return ok(json.dumps(DOC).encode())

    site = await sites(answer)
    lookups: list[str] = []
    loop = asyncio.get_running_loop()
    real = loop.getaddrinfo

    async def counted(host: Any, port: Any, **kwargs: Any) -> Any:
        lookups.append(str(host))
        if host == "twins.test":
            return await real("127.0.0.1", port, **kwargs)
        return await real(host, port, **kwargs)

    monkeypatch.setattr(loop, "getaddrinfo", counted)
    policy = FetchPolicy(hosts=("twins.test",), allow_private=True)
    fetcher = Fetcher(policy)
    try:
        got = await fetcher.fetch_document(f"http://twins.test:{site.port}/twins/a")
    finally:
        await fetcher.aclose()
    assert got.document == DOC
    assert site.seen[0].headers["host"] == f"twins.test:{site.port}"
    assert lookups == ["twins.test"]  # one lookup, by the guard; httpx connected to its answer
