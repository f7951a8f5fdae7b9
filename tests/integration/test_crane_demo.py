"""`twinlink demo` as a person runs it: with the crane's usual OPC UA port taken by another
socket, its connector still reaches its own OPC UA server, and everything it prints, from
start to Ctrl-C, is worth reading."""

from __future__ import annotations

import contextlib
import os
import re
import signal
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import httpx
import pytest

from ilmatar_crane import CranePorts
from tests.conftest import ROOT, free_port
from tests.integration._util import CRANE_SLUG, poll_until

pytestmark = pytest.mark.integration

OPCUA_PORT = CranePorts().opcua


@dataclass
class Demo:
    url: str
    token: str
    process: subprocess.Popen[str]
    lines: list[str] = field(default_factory=list)
    reader: threading.Thread | None = None

    def get(self, path: str) -> Any:
        headers = {"Authorization": f"Bearer {self.token}"}
        r = httpx.get(self.url + path, headers=headers, timeout=30)
        assert r.status_code == 200, r.text
        return r.json()

    @property
    def output(self) -> str:
        return "".join(self.lines)


@contextlib.contextmanager
def held_port(port: int) -> Iterator[None]:
    """Another program's socket listening on `port` (if one already does, it stays taken)."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind(("127.0.0.1", port))
        sock.listen()
    except OSError:
        pass  # already taken by something else, which is all the test needs
    try:
        yield
    finally:
        sock.close()


def _start(data_dir: Path) -> Demo:
    port = free_port()
    token = "tl_test_demo_" + os.urandom(12).hex()
    env = {k: v for k, v in os.environ.items() if not k.startswith("TWINLINK_")}
    # Info, so the test also sees the lines a reader would get with the server's usual level.
    env |= {"TWINLINK_ADMIN_TOKEN": token, "TWINLINK_LOG_LEVEL": "info", "NO_COLOR": "1"}
    env["TWINLINK_MQTT_PORT"] = "0"  # servers of tests run side by side
    args = ["demo", "--port", str(port), "--data-dir", str(data_dir)]
    process = subprocess.Popen(
        [sys.executable, "-m", "twinlink", *args],
        env=env,
        cwd=ROOT,
        text=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )
    demo = Demo(f"http://127.0.0.1:{port}", token, process)
    ready = threading.Event()

    def pump() -> None:
        assert process.stdout is not None
        for line in process.stdout:
            demo.lines.append(line)
            if line.startswith("twinlink serving at"):
                ready.set()
        ready.set()

    demo.reader = threading.Thread(target=pump, daemon=True)
    demo.reader.start()
    if not ready.wait(timeout=120) or process.poll() is not None:
        _end(demo)
        raise AssertionError(f"the demo did not start:\n{demo.output}")
    return demo


def _end(demo: Demo) -> None:
    if demo.process.poll() is None:
        demo.process.kill()
    demo.process.wait()
    if demo.reader is not None:
        demo.reader.join(timeout=10)
    if demo.process.stdout is not None:
        demo.process.stdout.close()


def _interrupt(demo: Demo) -> int:
    demo.process.send_signal(signal.SIGINT)  # Ctrl-C
    try:
        return demo.process.wait(timeout=60)
    except subprocess.TimeoutExpired:
        demo.process.kill()
        demo.process.wait()
        raise


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Demo]:
    with held_port(OPCUA_PORT):
        running = _start(tmp_path_factory.mktemp("demo"))
        try:
            yield running
        finally:
            _end(running)


def _plc(demo: Demo) -> dict[str, Any]:
    return demo.get(f"/api/v1/twins/{CRANE_SLUG}/connectors/plc")  # type: ignore[no-any-return]


def test_a_taken_opcua_port_is_replaced_and_the_connector_reaches_its_own_server(
    demo: Demo,
) -> None:
    url = _plc(demo)["config"]["url"]
    used = urlsplit(url).port
    assert used is not None and used != OPCUA_PORT, url
    [note] = [line for line in demo.lines if "Ports in use elsewhere" in line]
    assert f"{OPCUA_PORT} (OPC UA server) -> {used}" in note
    # Data comes in: the other socket on 4840 speaks no OPC UA, the crane's server does.
    poll_until(lambda: _plc(demo)["status"]["samples"] > 0, "samples from the crane", 60)
    assert _plc(demo)["status"]["state"] == "connected"
    # The documents the demo applied name the port really used, so people and the gateway
    # find the server the demo started.
    document = demo.get(f"/api/v1/twins/{CRANE_SLUG}")["document"]
    [opcua] = [f for f in document["features"] if f["name"] == "OPC UA server"]
    assert opcua["address"] == url
    assert f":{OPCUA_PORT}/" not in str(document)
    services = demo.get(f"/api/v1/twins/{CRANE_SLUG}/services")["services"]
    for service in services:
        health = demo.get(f"/api/v1/twins/{CRANE_SLUG}/services/{service['name']}/health")
        assert health["status"] == "up", (service["name"], health)


def test_tingen_is_deployed_from_its_package_with_its_rig_as_the_execute_phase(
    demo: Demo,
) -> None:
    deployment = demo.get("/api/v1/deployments/tingen")
    assert deployment["state"] == "running", deployment
    assert deployment["package"].startswith("lib:common/twins/tingen-rig@sha256:")
    fmu = demo.get("/api/v1/twins/tingen/processors/fmu")
    assert fmu["params"]["fmu"].startswith("lib:common/models/tingen-beam@sha256:")
    runs = demo.get("/api/v1/deployments/tingen/runs")["runs"]
    assert [r["state"] for r in runs if r["phase"] == "execute"] == ["running"], runs

    def computed() -> int:
        streams = demo.get("/api/v1/twins/tingen/streams")["streams"]
        return sum(s["samples"] for s in streams if s["name"] == "fmu")

    poll_until(lambda: computed() > 0, "the FMU's output on the rig's stream", 60)


def test_its_output_is_worth_reading_from_start_to_ctrl_c(demo: Demo) -> None:
    started = demo.output
    [twins] = [line for line in demo.lines if "Demo twins:" in line]
    slugs = re.findall(r"([a-z0-9-]+) \((?:created|updated|unchanged)\)", twins)
    assert sorted(slugs) == sorted(set(slugs)) and CRANE_SLUG in slugs and "tingen" in slugs
    assert _interrupt(demo) == 0, demo.output
    assert demo.reader is not None
    demo.reader.join(timeout=10)  # the last lines
    output = demo.output
    # One server process, said once, although the crane's four HTTP services run in it.
    for line in ("Started server process", "Shutting down", "Finished server process"):
        assert output.count(line) == 1, (line, output)
    # The simulated rig is stopped while the server still takes its batches, and the
    # connector before its server: neither complains at the end.
    stopped = output[len(started) :]
    for noise in ("unacknowledged", "connection lost", "cannot connect", "was lost", "Aborted"):
        assert noise not in stopped, stopped
    assert "Traceback" not in output and "Error" not in output, output
