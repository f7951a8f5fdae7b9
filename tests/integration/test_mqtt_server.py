"""MQTT in a real `twinlink up` (its embedded listener on a free port, as the tests' servers
run it): the status route and /metrics, and a device publishing with mosquitto_pub."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._mqtt import require_mosquitto
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration


def test_a_device_publishes_to_the_servers_embedded_listener(server: Server) -> None:
    require_mosquitto()
    slug = unique("mq")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
        r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "rig"})
        token = r.json()["token"]
        status = admin.get("/api/v1/mqtt").json()
        assert status["mode"] == "embedded" and status["state"] == "listening", status
        port = status["address"].rsplit(":", 1)[1]
        done = subprocess.run(
            ["mosquitto_pub", "-h", "127.0.0.1", "-p", port, "-u", "rig", "-P", token, "-q", "1",
             "-t", f"twinlink/{slug}/rig/telemetry", "-m", '{"angle": 0.25}'],
            capture_output=True, text=True, timeout=30,
        )  # fmt: skip
        assert done.returncode == 0, done.stdout + done.stderr
        # QoS 1: mosquitto_pub returned after the PUBACK, which comes once the sample is durable.
        latest = admin.get(f"/api/v1/twins/{slug}/streams/telemetry/latest").json()
        assert latest["values"]["angle"]["value"] == 0.25, latest
        deadline = time.monotonic() + 20
        while "twinlink_mqtt_samples_total 1.0" not in (metrics := admin.get("/metrics").text):
            assert time.monotonic() < deadline, [ln for ln in metrics.splitlines() if "mqtt" in ln]
            time.sleep(0.05)  # polling the real state
        refused = subprocess.run(
            ["mosquitto_pub", "-h", "127.0.0.1", "-p", port, "-u", "rig", "-P", "tld_wrong",
             "-t", f"twinlink/{slug}/rig/telemetry", "-m", "{}"],
            capture_output=True, text=True, timeout=30,
        )  # fmt: skip
        assert refused.returncode != 0 and "bad user name or password" in refused.stderr, refused
    viewer = make_user(server, unique("v"))
    with server.client(viewer) as c:
        assert_problem(c.get("/api/v1/mqtt"), 403)


def test_up_refuses_a_taken_mqtt_port_and_names_the_setting(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        env = {**os.environ, "TWINLINK_MQTT_PORT": str(port)}
        done = subprocess.run(
            [sys.executable, "-m", "twinlink", "up", "--port", "0", "--data-dir",
             str(tmp_path / "data")],
            env=env, capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    assert done.returncode != 0
    assert f"cannot listen for MQTT on 127.0.0.1:{port}" in done.stderr
    assert "TWINLINK_MQTT_PORT" in done.stderr and "Traceback" not in done.stderr
