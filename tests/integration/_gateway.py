"""Helpers for the gateway tests: twins with services, users with a role, raw HTTP requests
(for paths an HTTP client would normalise), and waiting with a deadline."""

from __future__ import annotations

import socket
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import apply, make_user, twin_doc, unique

T = TypeVar("T")
DEFAULT_TWIN = "gw-default"


def gateway_server(data_dir: Path, **env: str) -> Server:
    return start_server(data_dir, {"TWINLINK_GATEWAY_DEFAULT_TWIN": DEFAULT_TWIN, **env})


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A server whose default gateway twin is DEFAULT_TWIN, for the tests of one module."""
    srv = gateway_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def new_twin(server: Server, slug: str | None = None, **doc: Any) -> str:
    """A new twin (the admin is its owner); returns its slug."""
    slug = slug or unique("gw")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Gateway twin", slug=slug, **doc))
    return slug


def add_service(
    client: httpx.Client, slug: str, name: str, base_url: str, **settings: Any
) -> dict[str, Any]:
    r = client.post(
        f"/api/v1/twins/{slug}/services", json={"name": name, "base_url": base_url, **settings}
    )
    assert r.status_code == 201, r.text
    return r.json()  # type: ignore[no-any-return]


def user_with_role(server: Server, slug: str, role: str | None) -> tuple[str, str]:
    """A new user with `role` on the twin (None: no role); (username, token)."""
    username = unique(role or "stranger")
    token = make_user(server, username)
    if role is not None:
        with server.admin as admin:
            r = admin.put(f"/api/v1/twins/{slug}/roles/{username}", json={"role": role})
            assert r.status_code == 200, r.text
    return username, token


def path(slug: str, service: str, rest: str = "") -> str:
    return f"/twins/{slug}/services/{service}/{rest}"


def raw_request(
    server: Server, method: str, target: str, headers: dict[str, str] | None = None
) -> tuple[int, bytes]:
    """Send a request line exactly as given (no normalisation); (status, body)."""
    host, port = server.url.removeprefix("http://").split(":")
    lines = [f"{method} {target} HTTP/1.1", f"Host: {host}:{port}", "Connection: close"]
    lines += [f"{k}: {v}" for k, v in (headers or {}).items()]
    with socket.create_connection((host, int(port)), timeout=30) as sock:
        sock.sendall(("\r\n".join(lines) + "\r\n\r\n").encode("latin-1"))
        answer = b""
        while chunk := sock.recv(65536):
            answer += chunk
    head, _, body = answer.partition(b"\r\n\r\n")
    return int(head.split(b" ", 2)[1]), body


def wait_until(check: Callable[[], T | None], timeout_s: float = 20, what: str = "") -> T:
    """Poll `check` until it gives a value that is not None (or fail after `timeout_s`)."""
    deadline = time.monotonic() + timeout_s
    while True:
        found = check()
        if found is not None:
            return found
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what or check}")
        time.sleep(0.02)


def echoed(r: httpx.Response) -> dict[str, Any]:
    """The upstream's echo of a forwarded request."""
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def header_names(echo: dict[str, Any]) -> list[str]:
    return [k for k, _ in echo["headers"]]
