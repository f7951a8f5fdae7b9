"""The third-party plug-in example (examples/plugins, docs/plugins.md), installed from its own
pyproject.toml with pip as a user would, into a folder of its own that the server finds on
PYTHONPATH, and each of its plug-ins at work on a real server: the connector's samples reach
history, the blueprint's output stream is stored, the credential method's header reaches a
real upstream service through the gateway. Beside it a broken package is installed, which
the server lists as not available and otherwise ignores."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.conftest import EXAMPLES, Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._live import device_twin
from tests.integration._processors import MS, T0, create, post, wait_for
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from tests.integration._util import apply, assert_problem, poll_until, twin_doc, unique

pytestmark = pytest.mark.integration

EXAMPLE = EXAMPLES / "plugins"
S = 1_000_000_000
BROKEN_DIST = "twinlink_broken_plugin-1.0.dist-info"
BROKEN_ENTRY_POINTS = """
[twinlink.connectors]
broken = twinlink_broken_plugin:Thing
buggy = twinlink_buggy_plugin:Buggy

[twinlink.blueprints]
broken = twinlink_broken_plugin:Thing

[twinlink.credentials]
broken = twinlink_broken_plugin:Thing
"""


def _install_example(work: Path) -> Path:
    """pip install of the example into `work/site`, from a copy (pip builds in the source
    folder, and leaves build/ and *.egg-info there)."""
    source, site = work / "source", work / "site"
    shutil.copytree(EXAMPLE, source, ignore=shutil.ignore_patterns("build", "*.egg-info"))
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
               "--disable-pip-version-check", "--target", str(site), str(source)]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"pip could not install the example:\n{done.stderr}"
    return site


BUGGY = """
from pydantic import BaseModel
from twinlink.connectors.base import Connector


class Settings(BaseModel):
    pass


class Buggy(Connector):
    kind = "buggy"
    Config = Settings

    async def prepare(self) -> None:
        raise ZeroDivisionError("a bug on purpose")

    async def run(self) -> None: ...
"""


def _install_broken(site: Path) -> None:
    """A package with a module that fails on import, registered in all three groups, and a
    connector kind that loads but fails to start."""
    (site / "twinlink_broken_plugin.py").write_text("raise RuntimeError('broken on purpose')\n")
    (site / "twinlink_buggy_plugin.py").write_text(BUGGY)
    dist = site / BROKEN_DIST
    dist.mkdir()
    (dist / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: twinlink-broken-plugin\nVersion: 1.0\n"
    )
    (dist / "entry_points.txt").write_text(BROKEN_ENTRY_POINTS)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    site = _install_example(tmp_path_factory.mktemp("plugins"))
    _install_broken(site)
    path = os.pathsep.join(p for p in (str(site), os.environ.get("PYTHONPATH")) if p)
    srv = start_server(tmp_path_factory.mktemp("data"), {"PYTHONPATH": path})
    try:
        yield srv
    finally:
        stop_server(srv)


def _rows(server: Server, slug: str, stream: str, count: int) -> list[dict[str, Any]]:
    """The stream's stored samples, once there are `count` of them."""

    def stored() -> list[dict[str, Any]] | None:
        with server.admin as admin:
            r = admin.get(f"/api/v1/twins/{slug}/streams/{stream}/samples", params={"start": T0})
        rows: list[dict[str, Any]] = r.json()["rows"] if r.status_code == 200 else []
        return rows if len(rows) >= count else None

    return poll_until(stored, f"{count} samples in {stream}")  # type: ignore[no-any-return]


def test_the_example_is_listed_beside_the_built_in_plugins(server: Server) -> None:
    with server.admin as admin:
        listed = {k["kind"]: k for k in admin.get("/api/v1/connector-kinds").json()["kinds"]}
        blueprints = {b["name"]: b for b in admin.get("/api/v1/blueprints").json()["blueprints"]}
    assert {"udp", "opcua", "tcp_lines"} <= set(listed)
    assert listed["tcp_lines"]["secret_fields"] == ["token"]
    port = listed["tcp_lines"]["schema"]["properties"]["port"]
    assert (port["minimum"], port["maximum"]) == (0, 65535)
    average = blueprints["moving_average"]
    assert average["source"] == "installed" and "window" in average["params_schema"]["properties"]


def test_the_connector_streams_samples_into_history(server: Server) -> None:
    slug = unique("plug")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": "lines", "kind": "tcp_lines", "config": {"port": 0, "token": "tok-7f3a"}},
        )
    assert r.status_code == 201, r.text
    made = r.json()
    assert made["status"]["state"] == "listening"
    assert made["config"]["token_set"] is True and "tok-7f3a" not in r.text
    port = int(made["status"]["address"].rsplit(":", 1)[1])
    with socket.create_connection(("127.0.0.1", port), timeout=10) as refused:
        refused.sendall(b"not-the-token\nx=1\n")
        assert refused.makefile("rb").readline().startswith(b"refused")
    times = [T0 + i * 250 * MS for i in range(5)]
    lines = [f"time={t // S}.{t % S:09d} x={i * 1.5} y={-i}" for i, t in enumerate(times)]
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(b"tok-7f3a\n" + "\n".join(lines[:2]).encode() + b"\nx=oops\n")
        sock.sendall(("\n".join(lines[2:]) + "\n").encode())  # a second batch
        rows = _rows(server, slug, "telemetry", len(lines))
    assert [r["time"] for r in rows] == times
    assert [r["values"] for r in rows] == [{"x": i * 1.5, "y": -i} for i in range(5)]

    def counted() -> dict[str, Any] | None:
        with server.admin as admin:
            status = admin.get(f"/api/v1/twins/{slug}/connectors/lines").json()["status"]
        return status if status["samples"] == len(lines) else None

    status = poll_until(counted, "the connector's count of samples")
    assert status["errors"] == {"refused_client": 1, "bad_line": 1}


def test_the_blueprint_processes_a_stream(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="avg", blueprint="moving_average",
           params={"signals": ["x"], "window": 3})  # fmt: skip
    wait_for(server, slug, "avg", lambda p: p["state"] == "running")
    values = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0]
    post(server, device, 1, [{"x": v} for v in values[:4]])
    post(server, device, 2, [{"x": v} for v in values[4:]], t0=T0 + 4 * MS)  # state carries over
    rows = _rows(server, slug, "avg", len(values))
    expected = [float(np.mean(values[max(0, i - 2) : i + 1])) for i in range(len(values))]
    assert [r["values"]["x_avg"] for r in rows] == pytest.approx(expected, rel=1e-12)
    assert [r["time"] for r in rows] == [T0 + i * MS for i in range(len(values))]


def test_the_credential_methods_header_reaches_the_service(
    server: Server, upstream: Upstream
) -> None:
    slug = unique("plug")
    key = upstream.secrets.api_key
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Gateway twin", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/services",
            json={"name": "keyed", "base_url": upstream.base("key-header"),
                  "auth": {"method": "header_token", "token": key}},
        )  # fmt: skip
        assert r.status_code == 201, r.text
        assert r.json()["auth"] == {"method": "header_token", "header": "X-Api-Key",
                                    "token_set": True}  # fmt: skip
        assert key not in r.text
        # The caller's own X-Api-Key is replaced by the gateway's, not sent beside it.
        echo = admin.get(f"/twins/{slug}/services/keyed/echo/x", headers={"X-Api-Key": "mine"})
    assert echo.status_code == 200, echo.text
    sent = [v for k, v in echo.json()["headers"] if k == "x-api-key"]
    assert sent == [key]


def test_a_refused_token_is_reported_without_it(server: Server, upstream: Upstream) -> None:
    slug = unique("plug")
    wrong = "WRONG-token-5d1e"
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Gateway twin", slug=slug))
        r = admin.post(
            f"/api/v1/twins/{slug}/services",
            json={"name": "keyed", "base_url": upstream.base("key-header"),
                  "auth": {"method": "header_token", "token": wrong}},
        )  # fmt: skip
        assert r.status_code == 201, r.text
        answer = admin.get(f"/twins/{slug}/services/keyed/echo/x")
    problem = assert_problem(answer, 502)
    assert "header_token credentials" in problem["detail"] and wrong not in answer.text


def test_a_broken_package_is_listed_as_not_available_and_refused(server: Server) -> None:
    slug = unique("plug")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
        kinds = {k["kind"]: k for k in admin.get("/api/v1/connector-kinds").json()["kinds"]}
        blueprints = {b["name"]: b for b in admin.get("/api/v1/blueprints").json()["blueprints"]}
        connector = admin.post(f"/api/v1/twins/{slug}/connectors",
                               json={"name": "b", "kind": "broken", "config": {}})  # fmt: skip
        processor = admin.post(f"/api/v1/twins/{slug}/processors",
                               json={"name": "b", "blueprint": "broken"})  # fmt: skip
        service = admin.post(f"/api/v1/twins/{slug}/services",
                             json={"name": "b", "base_url": "http://127.0.0.1:9/",
                                   "auth": {"method": "broken"}})  # fmt: skip
    assert "broken on purpose" in kinds["broken"]["error"]
    assert "broken on purpose" in blueprints["broken"]["error"]
    assert "connector is not available here" in assert_problem(connector, 422)["detail"]
    assert "is broken" in assert_problem(processor, 422)["detail"]
    assert "'broken' is not available here" in assert_problem(service, 422)["detail"]
    assert "package twinlink-broken-plugin cannot be loaded, left out" in server.log()


def test_a_connector_kind_that_fails_to_start_is_refused_with_its_error(server: Server) -> None:
    slug = unique("plug")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
        r = admin.post(f"/api/v1/twins/{slug}/connectors",
                       json={"name": "b", "kind": "buggy", "config": {}})  # fmt: skip
        problem = assert_problem(r, 422)
        assert (
            problem["detail"] == "connector 'b' cannot start: ZeroDivisionError: a bug on purpose"
        )
        assert admin.get(f"/api/v1/twins/{slug}/connectors").json()["connectors"] == []
    assert (
        "Traceback" in server.log() and "connector " + slug + "/b failed to start" in server.log()
    )
