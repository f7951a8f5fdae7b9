from __future__ import annotations

from tests.conftest import Server


def test_health_needs_no_token(server: Server) -> None:
    with server.client() as c:
        r = c.get("/healthz")
    assert r.status_code == 200
    assert r.json()["status"] == "ok"
