"""The first thing to work: a real server answers /healthz without a token."""

from __future__ import annotations

import pytest

from tests.conftest import Server

pytestmark = pytest.mark.integration


def test_health_needs_no_token(server: Server) -> None:
    with server.client() as c:
        r = c.get("/healthz")
    assert r.status_code == 200
    assert r.json()["status"] == "ok"
