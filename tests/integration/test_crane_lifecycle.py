"""The crane's services as a whole: where the DT document points, a clean stop, the CLI."""

from __future__ import annotations

import asyncio
import json
import signal
import socket
import sys

import httpx
import psutil
import pytest
import yaml

from ilmatar_crane import CranePorts, CraneSettings, start_crane
from tests.conftest import EXAMPLES
from twinlink.gateway.spec import service_name
from twinlink_demo.crane_gateway import FEATURES

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]

FREE_PORTS = CranePorts(opcua=0, historian=0, bridge=0, cad=0, sensors=0)


async def test_dt_document_points_at_the_default_ports() -> None:
    public = yaml.safe_load((EXAMPLES / "ilmatar" / "ilmatar-public.yaml").read_text())
    features = {f["name"]: f for f in public["features"]}
    defaults = CranePorts()
    for feature, service in FEATURES.items():
        port = getattr(defaults, service)
        assert features[feature]["apiAddress"] == f"http://127.0.0.1:{port}/api/", feature
        assert service_name(feature) in {
            "historian",
            "opc-ua-server",
            "cad-store",
            "sensor-manager",
        }
    assert f"opc.tcp://127.0.0.1:{defaults.opcua}/ilmatar/" in json.dumps(features["OPC UA server"])


# Its own event loop, so that only this crane's tasks can be left over.
@pytest.mark.asyncio(loop_scope="function")
async def test_stop_closes_every_port_and_task() -> None:
    before = asyncio.all_tasks()
    crane = await start_crane(ports=FREE_PORTS, settings=CraneSettings(autopilot=False))
    ports = [crane.ports.opcua, crane.ports.historian, crane.ports.bridge]
    ports += [crane.ports.cad, crane.ports.sensors]
    assert len(set(ports)) == 5 and 0 not in ports
    await crane.stop()
    for port in ports:
        with pytest.raises(OSError):
            _, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.close()
            await writer.wait_closed()
    ours = {c.laddr.port for c in psutil.Process().net_connections("inet") if c.laddr}
    assert not ours & set(ports)
    assert asyncio.all_tasks() - before == set()


async def test_cli_prints_its_urls_and_stops_on_sigint() -> None:
    args = ["--opcua-port", "0", "--historian-port", "0", "--bridge-port", "0"]
    args += ["--cad-port", "0", "--sensors-port", "0", "--no-autopilot"]
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "ilmatar_crane", *args, stderr=asyncio.subprocess.PIPE
    )
    assert proc.stderr is not None
    try:
        async with asyncio.timeout(60):
            line = (await proc.stderr.readline()).decode()
        assert line.startswith("crane services ready "), line
        urls = json.loads(line.removeprefix("crane services ready "))
        assert set(urls) == {"opcua", "historian", "bridge", "cad", "sensors"}
        async with httpx.AsyncClient() as http:
            assert (await http.get(urls["historian"].removesuffix("api/") + "health")).is_success
        proc.send_signal(signal.SIGINT)
        async with asyncio.timeout(30):
            rest = (await proc.stderr.read()).decode()
            assert await proc.wait() == 0, rest
    finally:
        if proc.returncode is None:
            proc.kill()
            await proc.wait()


async def test_cli_refuses_a_taken_port_in_one_line() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        args = ["--opcua-port", str(port), "--historian-port", "0", "--bridge-port", "0"]
        args += ["--cad-port", "0", "--sensors-port", "0"]
        proc = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "ilmatar_crane", *args, stderr=asyncio.subprocess.PIPE
        )
        async with asyncio.timeout(60):
            _, err = await proc.communicate()
    assert proc.returncode == 1
    assert err.decode().splitlines() == [
        f"crane services could not start: port {port} (--opcua-port) on 127.0.0.1 is in use; "
        "choose another, or 0 for any free one"
    ]
