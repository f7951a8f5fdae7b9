"""Helpers for data-plane tests: a twin with a device, and a device speaking the WebSocket
protocol with the plain `websockets` client (no SDK), so the protocol itself is under test."""

from __future__ import annotations

import json
import sqlite3
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from websockets.sync.client import ClientConnection, connect

from tests.conftest import Server
from tests.integration._util import apply, twin_doc, unique

TIMEOUT_S = 30


def device_twin(
    server: Server, interface: dict[str, Any] | None = None, devices: int = 1
) -> tuple[str, list[str]]:
    """A new twin (with `interface` when given) and `devices` device tokens for it."""
    slug = unique("live")
    extra = {"interface": interface} if interface else {}
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, **extra))
        tokens = []
        for i in range(devices):
            r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": f"dev{i}"})
            assert r.status_code == 201, r.text
            tokens.append(r.json()["token"])
    return slug, tokens


def ws_url(server: Server, path: str) -> str:
    return server.url.replace("http://", "ws://", 1) + path


@contextmanager
def device_socket(server: Server, token: str | None) -> Iterator[ClientConnection]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    with connect(
        ws_url(server, "/api/v1/device/ws"), additional_headers=headers, open_timeout=TIMEOUT_S
    ) as ws:
        yield ws


def receive(ws: ClientConnection, kind: str | None = None) -> dict[str, Any]:
    """The next message (of type `kind`, skipping others), waiting at most TIMEOUT_S."""
    deadline = time.monotonic() + TIMEOUT_S
    while True:
        message = json.loads(ws.recv(timeout=max(0.0, deadline - time.monotonic())))
        if kind is None or message["type"] == kind:
            return message  # type: ignore[no-any-return]


def send(ws: ClientConnection, message: dict[str, Any]) -> None:
    ws.send(json.dumps(message))


def batch(seq: int, rows: list[dict[str, Any]], **extra: Any) -> dict[str, Any]:
    return {"type": "samples", "seq": seq, "samples": rows, **extra}


def _read(path: Any, sql: str, *args: Any) -> list[Any]:
    conn = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        return conn.execute(sql, args).fetchall()
    finally:
        conn.close()


def twin_id(server: Server, slug: str) -> int:
    rows = _read(server.data_dir / "twinlink.sqlite3", "SELECT id FROM twins WHERE slug = ?", slug)
    return int(rows[0][0])


def stored_values(server: Server, slug: str, signal: str) -> list[Any]:
    """Every stored value of one signal of twin `slug` in storage order, read straight from
    the history file (read-only), so storage is checked independently of the query API: its
    blocks by time, then its small batches still staged (newer than any of its blocks)."""
    import orjson

    from twinlink.store.sqlite.history.codec import decode_values

    path, twin = server.data_dir / "history.db", twin_id(server, slug)
    rows = _read(
        path,
        "SELECT kind, vals FROM blocks JOIN series ON series.id = blocks.series_id "
        "WHERE twin_id = ? AND signal = ? ORDER BY t0, blocks.rowid",
        twin,
        signal,
    )
    values = [
        v.item() if hasattr(v, "item") else v
        for kind, blob in rows
        for v in decode_values(kind, blob)
    ]
    for (body,) in _read(path, "SELECT body FROM staged WHERE twin_id = ? ORDER BY id", twin):
        for _, name, _, staged in orjson.loads(body):
            if name == signal:
                values.extend(staged)
    return values
