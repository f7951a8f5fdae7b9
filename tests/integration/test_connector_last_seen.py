"""A device a connector speaks for (UDP here; OPC UA goes the same way) is connected and seen
while the connector runs, and keeps when it was last seen after it stops, across a restart,
as the devices API shows it (the web app reads it there)."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import datetime
from typing import Any

import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._util import apply, twin_doc, unique

pytestmark = pytest.mark.integration


@pytest.fixture
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A server of this test alone: it is restarted."""
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def _device(server: Server, slug: str, name: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/devices/{name}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def _time(text: str) -> datetime:
    return datetime.fromisoformat(text.replace("Z", "+00:00"))


def test_a_connector_s_device_is_seen_while_it_runs_and_after(server: Server) -> None:
    slug = unique("seen")
    body = {"name": "logger", "kind": "udp", "config": {"port": 0, "format": "json"}}
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
        assert admin.post(f"/api/v1/twins/{slug}/connectors", json=body).status_code == 201
    running = _device(server, slug, "logger")
    assert running["connected"] is True
    assert running["last_seen"] is not None  # was "never" while connected
    with server.admin as admin:
        r = admin.patch(f"/api/v1/twins/{slug}/connectors/logger", json={"enabled": False})
        assert r.status_code == 200, r.text
        listed = admin.get(f"/api/v1/twins/{slug}/devices").json()["devices"]
    stopped = {d["name"]: d for d in listed}["logger"]
    assert stopped["connected"] is False
    assert stopped["last_seen"] is not None
    assert _time(stopped["last_seen"]) >= _time(running["created"])
    # Written down: after a restart the device still shows when it was last seen.
    stop_server(server)
    again = restart_server(server)
    try:
        after = _device(again, slug, "logger")
        assert after["connected"] is False
        assert after["last_seen"] == stopped["last_seen"]
    finally:
        stop_server(again)
