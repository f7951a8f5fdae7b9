"""`twinlink simulate tingen` against a real server: it streams, obeys pause and start, and
applies a desired filter weight."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.conftest import EXAMPLES, Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply_file

pytestmark = pytest.mark.integration

ANGLE = "Cantilever_Angle_radians"


def _until(what: str, check: Callable[[], Any], timeout: float = 60) -> Any:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        found = check()
        if found:
            return found
        time.sleep(0.05)  # polling a condition, with a deadline
    raise AssertionError(f"timed out waiting for {what}")


@pytest.fixture
def rig(server: Server) -> Iterator[subprocess.Popen[bytes]]:
    with server.admin as admin:
        assert apply_file(admin, EXAMPLES / "tingen" / "tingen.yaml").status_code == 200
    env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token}
    proc = subprocess.Popen(
        [sys.executable, "-m", "twinlink", "simulate", "tingen", "--rate", "50"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        yield proc
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err.decode(errors="replace")


def _ns(iso: str) -> int:
    from datetime import datetime

    return int(datetime.fromisoformat(iso.replace("Z", "+00:00")).timestamp() * 1e6) * 1000


def test_the_simulated_rig_streams_and_obeys(server: Server, rig: subprocess.Popen[bytes]) -> None:
    with server.admin as admin:

        def latest() -> int | None:
            r = admin.get("/api/v1/twins/tingen/streams/telemetry/latest")
            if r.status_code != 200:
                return None
            found = r.json().get("values", r.json()).get(ANGLE)
            return int(found["time"]) if found else None

        def reported(name: str) -> Any:
            r = admin.get("/api/v1/twins/tingen/devices/simulator/properties")
            return r.json()["reported"].get(name, {}).get("value") if r.status_code == 200 else None

        first = _until("the rig's first samples", latest)
        _until("a later sample", lambda: (latest() or 0) > first)
        assert 0.0 <= _value(admin) <= 1.0

        r = admin.patch(
            "/api/v1/twins/tingen/devices/simulator/properties/desired", json={"filter_k": 0.5}
        )
        assert r.status_code == 200, r.text
        _until("filter_k reported as 0.5", lambda: reported("filter_k") == 0.5)

        paused = admin.post("/api/v1/twins/tingen/commands", json={"name": "pause"})
        assert paused.json()["state"] == "succeeded", paused.text
        assert reported("paused") is True
        paused_at = _ns(paused.json()["finished"])
        resumed = admin.post("/api/v1/twins/tingen/commands", json={"name": "start"})
        assert resumed.json()["state"] == "succeeded", resumed.text
        started_at = _ns(resumed.json()["created"])
        _until("samples after start", lambda: (latest() or 0) > started_at)

        rig.send_signal(signal.SIGTERM)  # it sends what it made, then exits
        rig.wait(timeout=30)
        gap = admin.get(
            "/api/v1/twins/tingen/streams/telemetry/samples",
            params={"signals": ANGLE, "start": str(paused_at), "end": str(started_at)},
        )
        assert gap.status_code == 200, gap.text
        assert gap.json()["rows"] == [], "the rig sent samples while paused"


def _value(admin: Any) -> float:
    body = admin.get("/api/v1/twins/tingen/streams/telemetry/latest").json()
    return float(body.get("values", body)[ANGLE]["value"])
