"""Connector management through the API and CLI of a real server, with UDP datasources
receiving real datagrams on loopback (docs/connectors.md)."""

from __future__ import annotations

import socket
import subprocess
import sys
from pathlib import Path
from typing import Any

import httpx
import orjson
import pytest

from tests.conftest import ROOT, Server, restart_server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors
from tests.integration._util import apply, assert_problem, make_user, poll_until, twin_doc, unique

pytestmark = pytest.mark.integration


def _twin(server: Server) -> str:
    slug = unique("conn")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug))
    return slug


def _create(server: Server, slug: str, expect: int = 201, **body: Any) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/connectors", json=body)
    assert r.status_code == expect, r.text
    return r.json()  # type: ignore[no-any-return]


def _get(server: Server, slug: str, name: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/connectors/{name}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def _port(view: dict[str, Any]) -> int:
    return int(view["status"]["address"].rsplit(":", 1)[1])


def _send(port: int, *payloads: dict[str, Any]) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for p in payloads:
            s.sendto(orjson.dumps(p), ("127.0.0.1", port))


def _count(server: Server, slug: str, stream: str) -> int:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/streams")
    assert r.status_code == 200, r.text
    return sum(s["count"] for s in r.json()["streams"] if s["name"] == stream)


def _samples_arrive(server: Server, slug: str, port: int, stream: str = "telemetry") -> int:
    """Send datagrams until the stream grows (UDP may drop one), return the new count."""
    before = _count(server, slug, stream)

    def grown() -> int:
        _send(port, {"angle": 0.25, "force": 2.0})
        now = _count(server, slug, stream)
        return now if now > before else 0

    return int(poll_until(grown, f"samples in {stream}"))


def _port_is_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def test_kinds_are_listed_with_their_schema(server: Server) -> None:
    with server.admin as admin:
        kinds = {k["kind"]: k for k in admin.get("/api/v1/connector-kinds").json()["kinds"]}
    assert {"udp", "opcua"} <= set(kinds)
    assert "port" in kinds["udp"]["schema"]["properties"]


def test_a_udp_connector_feeds_its_own_device(server: Server) -> None:
    slug = _twin(server)
    made = _create(server, slug, name="logger", kind="udp", config={"port": 0, "format": "json"})
    assert made["device"] == "logger" and made["enabled"] is True
    assert made["status"]["state"] == "listening"
    port = _port(made)
    _samples_arrive(server, slug, port)
    view = _get(server, slug, "logger")
    assert view["status"]["messages"] >= 1 and view["status"]["samples"] >= 1
    assert view["status"]["last_message_ns"] is not None
    with server.admin as admin:
        listed = admin.get(f"/api/v1/twins/{slug}/devices").json()["devices"]
        metrics = admin.get("/metrics").text
    devices = {d["name"]: d for d in listed}
    assert devices["logger"]["connected"] is True
    labels = 'connector="logger",kind="udp"'  # the exposition sorts labels by name
    assert f'twinlink_connector_state{{{labels},state="listening",twin="{slug}"}} 1.0' in metrics
    prefix = f'twinlink_connector_samples_total{{{labels},twin="{slug}"}}'
    samples = [ln for ln in metrics.splitlines() if ln.startswith(prefix)]
    assert samples and float(samples[0].rsplit(" ", 1)[1]) >= 1


def test_changes_restart_it_and_a_bad_change_changes_nothing(server: Server) -> None:
    slug = _twin(server)
    port = _port(_create(server, slug, name="dl", kind="udp", config={"port": 0, "format": "json"}))
    with server.admin as admin:
        r = admin.patch(f"/api/v1/twins/{slug}/connectors/dl", json={"config": {"stream": "lab"}})
        assert r.status_code == 200, r.text
        port = _port(r.json())
        _samples_arrive(server, slug, port, "lab")

        r = admin.patch(f"/api/v1/twins/{slug}/connectors/dl", json={"config": {"nan": "maybe"}})
        assert "nan" in assert_problem(r, 422)["detail"]
        still = admin.get(f"/api/v1/twins/{slug}/connectors/dl").json()
        assert still["config"]["stream"] == "lab" and still["status"]["state"] == "listening"
        _samples_arrive(server, slug, _port(still), "lab")

        r = admin.post(f"/api/v1/twins/{slug}/connectors/dl/stop")
        assert r.status_code == 200 and r.json()["enabled"] is False
        assert r.json()["status"]["state"] == "stopped"
        assert _port_is_free(_port(still))
        r = admin.post(f"/api/v1/twins/{slug}/connectors/dl/start")
        assert r.status_code == 200 and r.json()["status"]["state"] == "listening"

        assert admin.delete(f"/api/v1/twins/{slug}/connectors/dl").status_code == 204
        assert_problem(admin.get(f"/api/v1/twins/{slug}/connectors/dl"), 404)
        assert _port_is_free(_port(r.json()))


def test_a_connector_that_cannot_start_is_not_kept(server: Server) -> None:
    slug = _twin(server)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("127.0.0.1", 0))
        port = taken.getsockname()[1]
        with server.admin as admin:
            r = admin.post(
                f"/api/v1/twins/{slug}/connectors",
                json={"name": "busy", "kind": "udp", "config": {"port": port, "format": "json"}},
            )
            assert "in use" in assert_problem(r, 422)["detail"]
            assert admin.get(f"/api/v1/twins/{slug}/connectors").json()["connectors"] == []
            devices = admin.get(f"/api/v1/twins/{slug}/devices").json()["devices"]
            assert [d["name"] for d in devices] == []


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ({"name": "x", "kind": "carrier-pigeon", "config": {}}, "unknown connector kind"),
        ({"name": "x", "kind": "udp", "config": {"format": "json"}}, "port"),
        ({"name": "x", "kind": "udp", "config": {"port": 0, "colour": "red"}}, "colour"),
        ({"name": "bad name!", "kind": "udp", "config": {"port": 0}}, "name"),
        ({"name": "x", "kind": "udp", "config": {"port": 0}, "extra": 1}, "extra"),
    ],
)
def test_bad_requests_say_what_is_wrong(server: Server, body: dict[str, Any], words: str) -> None:
    slug = _twin(server)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/connectors", json=body)
        assert words in assert_problem(r, 422)["detail"]
        assert admin.get(f"/api/v1/twins/{slug}/connectors").json()["connectors"] == []


def test_only_admins_manage_connectors_and_viewers_see_them(server: Server) -> None:
    slug = _twin(server)
    _create(server, slug, name="seen", kind="udp", config={"port": 0, "format": "json"})
    name = unique("ed")
    me = httpx.Client(
        base_url=server.url, headers={"Authorization": f"Bearer {make_user(server, name)}"}
    )
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}/roles/{name}", json={"role": "editor"})
        assert r.status_code in (200, 204), r.text
    with me:
        listed = me.get(f"/api/v1/twins/{slug}/connectors")
        assert [c["name"] for c in listed.json()["connectors"]] == ["seen"]
        r = me.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": "mine", "kind": "udp", "config": {"port": 0}},
        )
        assert "admins" in assert_problem(r, 403)["detail"]
        assert_problem(me.delete(f"/api/v1/twins/{slug}/connectors/seen"), 403)
        assert_problem(me.get(f"/api/v1/twins/{slug}/connectors/nothing"), 404)
    with server.client() as anon:
        assert_problem(anon.get(f"/api/v1/twins/{slug}/connectors"), 401)


def test_enabled_connectors_start_again_with_the_server(tmp_path: Path) -> None:
    server = start_server(tmp_path / "data")
    try:
        slug = _twin(server)
        _create(server, slug, name="on", kind="udp", config={"port": 0, "format": "json"})
        _create(server, slug, name="off", kind="udp", enabled=False,
                config={"port": 0, "format": "json"})  # fmt: skip
    finally:
        stop_server(server)
    server = restart_server(server)
    try:
        on, off = _get(server, slug, "on"), _get(server, slug, "off")
        assert on["status"]["state"] == "listening"
        assert off["status"]["state"] == "stopped" and off["enabled"] is False
        _samples_arrive(server, slug, _port(on))
    finally:
        stop_server(server)


def test_twinlink_apply_creates_then_changes_connectors(server: Server, tmp_path: Path) -> None:
    slug = _twin(server)
    path = tmp_path / "connectors.yaml"

    def run(stream: str) -> str:
        path.write_text(
            f"twin: {slug}\nconnectors:\n  - name: udp-in\n    kind: udp\n"
            f"    config: {{port: 0, format: json, stream: {stream}}}\n"
        )
        env = {"TWINLINK_URL": server.url, "TWINLINK_TOKEN": server.admin_token,
               "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}  # fmt: skip
        done = subprocess.run(
            [sys.executable, "-m", "twinlink", "apply", "-f", str(path)],
            env=env, cwd=ROOT, capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        return done.stdout

    assert f"connector/{slug}/udp-in created" in run("a")
    assert f"connector/{slug}/udp-in updated" in run("b")
    view = _get(server, slug, "udp-in")
    assert view["config"]["stream"] == "b" and view["status"]["state"] == "listening"


def test_deleting_its_device_or_twin_stops_it(server: Server) -> None:
    slug = _twin(server)
    first = _port(_create(server, slug, name="a", kind="udp", config={"port": 0, "format": "json"}))
    second = _port(
        _create(server, slug, name="b", kind="udp", config={"port": 0, "format": "json"})
    )
    with server.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}/devices/a").status_code in (200, 204)
        names = [
            c["name"] for c in admin.get(f"/api/v1/twins/{slug}/connectors").json()["connectors"]
        ]
        assert names == ["b"]
        assert _port_is_free(first)
        assert admin.delete(f"/api/v1/twins/{slug}").status_code in (200, 204)
    poll_until(lambda: _port_is_free(second), "the deleted twin's connector to stop")
