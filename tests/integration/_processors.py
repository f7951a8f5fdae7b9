"""Helpers for processor tests: a server with the test blueprints folder, live watching of a
processor's output stream, and waiting on a processor's state through the API."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import orjson
import pytest
from websockets.sync.client import ClientConnection, connect

from tests.conftest import ROOT, Server, start_server, stop_server
from tests.integration._live import TIMEOUT_S, ws_url

BLUEPRINTS = ROOT / "tests" / "blueprints"
T0 = 1_732_200_000_000_000_000
MS = 1_000_000


def processor_server(data_dir: Path, **env: str) -> Server:
    return start_server(data_dir, {"TWINLINK_BLUEPRINTS_DIR": str(BLUEPRINTS), **env})


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A server with the test blueprints folder, for the tests of one module."""
    srv = processor_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


@contextmanager
def watching(server: Server, slug: str, stream: str) -> Iterator[ClientConnection]:
    """A live connection subscribed to one stream of a twin."""
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    with connect(
        ws_url(server, "/api/v1/live"), additional_headers=headers, open_timeout=TIMEOUT_S
    ) as ws:
        assert _recv(ws)["type"] == "welcome"
        ws.send(orjson.dumps({"op": "subscribe", "id": "s", "twin": slug, "stream": stream}))
        answer = _recv(ws)
        assert answer["type"] == "subscribed", answer
        yield ws


def _recv(ws: ClientConnection, timeout: float = TIMEOUT_S) -> dict[str, Any]:
    return orjson.loads(ws.recv(timeout=timeout))  # type: ignore[no-any-return]


def samples_until(
    ws: ClientConnection, enough: Callable[[list[dict[str, Any]]], bool]
) -> list[dict[str, Any]]:
    """Samples from the subscription until `enough(all so far)` holds (or TIMEOUT_S)."""
    got: list[dict[str, Any]] = []
    deadline = time.monotonic() + TIMEOUT_S
    while not enough(got):
        message = _recv(ws, max(0.01, deadline - time.monotonic()))
        if message["type"] == "samples":
            got.extend(message["samples"])
    return got


def post(server: Server, device: str, seq: int, values: list[dict[str, Any]], t0: int = T0) -> None:
    rows = [{"time": t0 + i * MS, "values": v} for i, v in enumerate(values)]
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": rows})
    assert r.status_code == 200 and r.json()["accepted"] == len(rows), r.text


def create(server: Server, slug: str, **spec: Any) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors", json=spec)
    assert r.status_code == 201, r.text
    return r.json()  # type: ignore[no-any-return]


def processor(server: Server, slug: str, name: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/processors/{name}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def wait_for(
    server: Server, slug: str, name: str, check: Callable[[dict[str, Any]], bool]
) -> dict[str, Any]:
    """Poll the processor until `check` holds; its last view (fails after TIMEOUT_S)."""
    deadline = time.monotonic() + TIMEOUT_S
    while True:
        view = processor(server, slug, name)
        if check(view):
            return view
        assert time.monotonic() < deadline, f"processor never reached the state: {view}"
        time.sleep(0.05)


def events(server: Server, slug: str, name: str, kind: str | None = None) -> list[dict[str, Any]]:
    params = {"kind": kind} if kind else {}
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/processors/{name}/events", params=params)
    assert r.status_code == 200, r.text
    return r.json()["events"]  # type: ignore[no-any-return]
