"""Fetching another instance's DT document (docs/federation.md "Relations across
instances").

Redirects are followed here, not by httpx: every hop goes through the guard (guard.py), the
connection goes to the address the guard checked (the request names the host in `Host` and
in TLS's SNI, so certificates are still checked against the name), a peer's token is sent
only to that peer's exact origin, and a loop is refused by name. One deadline covers the
whole fetch, every hop included, and a body is read only up to the size limit.
"""

from __future__ import annotations

import asyncio
import logging
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any
from urllib.parse import urljoin, urlsplit, urlunsplit

import httpx

from twinlink.domain.errors import DocumentError
from twinlink.federation.guard import FetchFailed, FetchPolicy, FetchRefused, Target, resolve
from twinlink.registry.documents import parse_documents

__all__ = ["FetchFailed", "FetchPolicy", "FetchRefused", "Fetched", "Fetcher"]

log = logging.getLogger("twinlink.federation")
ACCEPT = "application/json, application/yaml;q=0.9, text/yaml;q=0.8, */*;q=0.1"
USER_AGENT = "twinlink-federation"
_REDIRECTS = {301, 302, 303, 307, 308}
_GONE = {404, 410}


@dataclass
class Fetched:
    url: str  # after redirects: where the document was found
    status: int
    document: dict[str, Any] | None  # None when not_modified
    etag: str | None
    last_modified: str | None
    not_modified: bool


def _no_tokens(origin: str) -> str | None:
    return None


def _address_url(target: Target, address: str) -> str:
    """The target's URL with the checked address in place of the host name."""
    parts = urlsplit(target.url)
    host = f"[{address}]" if ":" in address else address
    return urlunsplit((target.scheme, f"{host}:{target.port}", parts.path or "/", parts.query, ""))


def _host_header(target: Target) -> str:
    return target.origin.split("://", 1)[1]


def _is_html(content_type: str) -> bool:
    return "html" in content_type


class Fetcher:
    """One per process; holds a connection pool (keyed by checked address)."""

    def __init__(
        self, policy: FetchPolicy, tokens: Callable[[str], str | None] = _no_tokens
    ) -> None:
        self.policy = policy
        self._tokens = tokens
        # trust_env=False: no proxy from the environment (it would connect instead of us, to
        # an address we did not check) and no ~/.netrc credentials sent to strangers.
        self._client = httpx.AsyncClient(
            follow_redirects=False,
            trust_env=False,
            timeout=httpx.Timeout(policy.timeout_s),
            limits=httpx.Limits(max_connections=32, max_keepalive_connections=8),
        )

    async def aclose(self) -> None:
        await self._client.aclose()

    async def fetch_document(
        self, url: str, *, etag: str | None = None, last_modified: str | None = None
    ) -> Fetched:
        """GET the document at `url` (see the module's docstring); FetchRefused when the
        guard refuses a hop, FetchFailed when the other side fails."""
        try:
            async with asyncio.timeout(self.policy.timeout_s):
                return await self._follow(url, etag, last_modified)
        except TimeoutError as err:
            raise FetchFailed(
                f"{url!r} did not answer within {self.policy.timeout_s:g} s"
                " (TWINLINK_FEDERATION_TIMEOUT_S)"
            ) from err

    async def _follow(self, url: str, etag: str | None, last_modified: str | None) -> Fetched:
        seen = [url]
        tried_index = False
        current = url
        while True:
            target = await resolve(current, self.policy)
            status, headers, body = await self._get(target, etag, last_modified)
            if status in _REDIRECTS and headers.get("location"):
                nxt = urljoin(current, headers["location"])
                if nxt.split("#", 1)[0] in seen:
                    chain = " -> ".join([*seen, nxt])
                    raise FetchFailed(f"{url!r}: a redirect loop: {chain}")
                self._hop(url, seen, nxt)
                current = nxt
                continue
            if status == 304:
                return Fetched(current, 304, None, etag, last_modified, True)
            if status in _GONE:
                raise FetchFailed(f"{current!r} answered {status}: no document there", status)
            if status != 200:
                raise FetchFailed(f"{current!r} answered {status}, not a document", status)
            content_type = headers.get("content-type", "").lower()
            if _is_html(content_type) and not tried_index:
                # A Twinbase hosting-iri is a folder whose page is HTML; its document is
                # index.json beside it (as the dtweb client reads it).
                tried_index = True
                nxt = current.split("#", 1)[0].split("?", 1)[0].rstrip("/") + "/index.json"
                self._hop(url, seen, nxt)
                current = nxt
                continue
            document = self._document(current, body, content_type)
            return Fetched(
                current,
                status,
                document,
                headers.get("etag"),
                headers.get("last-modified"),
                False,
            )

    def _hop(self, url: str, seen: list[str], nxt: str) -> None:
        if len(seen) > self.policy.max_hops:
            raise FetchFailed(
                f"{url!r}: more than {self.policy.max_hops} redirects"
                " (TWINLINK_FEDERATION_MAX_HOPS): " + " -> ".join([*seen, nxt])
            )
        seen.append(nxt.split("#", 1)[0])

    async def _get(
        self, target: Target, etag: str | None, last_modified: str | None
    ) -> tuple[int, dict[str, str], bytes]:
        headers = {
            "Host": _host_header(target),
            "Accept": ACCEPT,
            "Accept-Encoding": "gzip",
            "User-Agent": USER_AGENT,
        }
        if etag:
            headers["If-None-Match"] = etag
        if last_modified:
            headers["If-Modified-Since"] = last_modified
        token = self._tokens(target.origin)
        if token:  # this hop's own origin only: never carried across a redirect
            headers["Authorization"] = f"Bearer {token}"
        extensions = {"sni_hostname": target.host} if target.scheme == "https" else {}
        last: Exception | None = None
        for address in target.addresses:
            request = self._client.build_request(
                "GET", _address_url(target, address), headers=headers, extensions=extensions
            )
            try:
                response = await self._client.send(request, stream=True)
            except httpx.ConnectError as err:  # the next address may answer
                last = err
                continue
            except httpx.HTTPError as err:
                raise FetchFailed(f"{target.url!r} could not be read: {_reason(err)}") from err
            try:
                body = await self._read(target, response)
            except httpx.HTTPError as err:
                raise FetchFailed(f"{target.url!r} could not be read: {_reason(err)}") from err
            finally:
                await response.aclose()
            return response.status_code, {k.lower(): v for k, v in response.headers.items()}, body
        raise FetchFailed(f"{target.url!r} could not be reached: {_reason(last)}")

    async def _read(self, target: Target, response: httpx.Response) -> bytes:
        if response.status_code != 200:
            return b""  # redirects and errors: their bodies are not needed
        limit = self.policy.max_bytes
        declared = response.headers.get("content-length", "")
        if declared.isdigit() and int(declared) > limit:
            raise FetchFailed(_too_large(target, limit, int(declared)))
        chunks: list[bytes] = []
        size = 0
        async for chunk in response.aiter_raw():
            size += len(chunk)
            if size > limit:  # stop reading: the rest is never downloaded
                raise FetchFailed(_too_large(target, limit, size))
            chunks.append(chunk)
        return _decoded(b"".join(chunks), response, limit, target)

    def _document(self, url: str, body: bytes, content_type: str) -> dict[str, Any]:
        kind = "application/json" if "json" in content_type else "application/yaml"
        try:
            docs = parse_documents(body, kind, self.policy.max_bytes)
        except DocumentError as err:
            raise FetchFailed(f"{url!r} is not a DT document: {err.problem_detail()}") from err
        data = docs[0].data if docs else None
        if len(docs) != 1 or not isinstance(data, dict):
            raise FetchFailed(f"{url!r} is not a DT document: expected one object")
        return data


def _too_large(target: Target, limit: int, size: int) -> str:
    return (
        f"{target.url!r} is larger than {limit} bytes (at least {size}; TWINLINK_FEDERATION_MAX_KB)"
    )


def _decoded(raw: bytes, response: httpx.Response, limit: int, target: Target) -> bytes:
    """The body without its content coding (gzip...), still within the limit: a small
    compressed body must not unpack into a huge one."""
    coding = response.headers.get("content-encoding", "identity").strip().lower()
    if coding in ("", "identity"):
        return raw
    if coding not in ("gzip", "deflate"):
        raise FetchFailed(f"{target.url!r} uses the content coding {coding!r}, not gzip")
    wbits = 16 + zlib.MAX_WBITS if coding == "gzip" else zlib.MAX_WBITS
    try:
        out = zlib.decompressobj(wbits).decompress(raw, limit + 1)
    except zlib.error as err:
        raise FetchFailed(f"{target.url!r} sent a broken {coding} body: {err}") from err
    if len(out) > limit:
        raise FetchFailed(_too_large(target, limit, len(out)))
    return out


def _reason(err: Exception | None) -> str:
    if err is None:
        return "no address"
    return str(err) or type(err).__name__
