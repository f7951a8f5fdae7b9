"""The API contract: /openapi.json describes every answer (errors as RFC 9457 problems), and
a real server answers as described. A walk through every operation with real data (a twin
with an interface, a device sending samples, commands, properties, a processor, an FMU, a
gateway service, a connector) checks each answer's status, media type and body against the
description (tests/integration/_contract.py), then that every operation answered a 2xx."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
import time
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import httpx
import orjson
import pytest

from tests.conftest import ROOT, FmuFiles, Server, start_server, stop_server
from tests.integration._contract import Contract
from tests.integration._runs import tar_of
from tests.integration._util import YAML_HEADERS, make_user, poll_until, twin_doc, unique

pytestmark = pytest.mark.integration
UI = ROOT / "ui"

INTERFACE = {
    "signals": [{"name": "x", "unit": "m"}, {"name": "label", "type": "string"}],
    "commands": [{"name": "go", "parameters": [{"name": "v", "type": "number"}]}],
    "properties": [{"name": "speed", "type": "number", "writable": True}],
}


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """Loopback fetches allowed: the remote twins' import reads this server's own index."""
    srv = start_server(
        tmp_path_factory.mktemp("data"), {"TWINLINK_FEDERATION_ALLOW_PRIVATE": "true"}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture(scope="module")
def spec(server: Server) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get("/openapi.json")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


@pytest.fixture(scope="module")
def contract(spec: dict[str, Any]) -> Contract:
    return Contract(spec)


@dataclass
class Walk:
    server: Server
    contract: Contract
    admin: httpx.Client
    slug: str

    def client(self, token: str | None = None) -> httpx.Client:
        return self.contract.client(self.server.url, token)

    def ok(self, r: httpx.Response, status: int = 200) -> Any:
        assert r.status_code == status, f"{r.request.method} {r.request.url}: {r.text[:500]}"
        media = r.headers.get("content-type", "").split(";")[0]
        return r.json() if r.content and media == "application/json" else None


@pytest.fixture
def walk(server: Server, contract: Contract) -> Iterator[Walk]:
    slug = unique("contract")
    with contract.client(server.url, server.admin_token) as admin:
        yield Walk(server, contract, admin, slug)


# -- the description itself -------------------------------------------------------------------


def test_every_operation_describes_its_answers_and_errors(spec: dict[str, Any]) -> None:
    """A 2xx with a schema (or a 204), errors as problem+json of the Problem model, and
    nothing of FastAPI's own validation error, which this API never sends."""
    missing, not_problems = [], []
    for path, item in spec["paths"].items():
        for method, op in item.items():
            where = f"{method.upper()} {path}"
            answers = {s: r for s, r in op["responses"].items() if s.startswith("2")}
            described = [
                s
                for s, r in answers.items()
                if s == "204" or any(c.get("schema") for c in r.get("content", {}).values())
            ]
            if not described:
                missing.append(where)
            for status, response in op["responses"].items():
                if int(status) >= 400 and response.get("content") != {
                    "application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}
                }:
                    not_problems.append(f"{where} {status}")
    assert not missing, f"operations without a described answer: {missing}"
    assert not not_problems, f"errors not described as problems: {not_problems}"
    assert "HTTPValidationError" not in spec["components"]["schemas"]
    assert {"title", "status", "detail"} <= set(
        spec["components"]["schemas"]["Problem"]["required"]
    )


def test_routes_that_need_a_token_declare_401(spec: dict[str, Any]) -> None:
    without = [
        f"{method.upper()} {path}"
        for path, item in spec["paths"].items()
        for method, op in item.items()
        if op.get("security") and "401" not in op["responses"]
    ]
    assert not without


# -- a real server answers as described --------------------------------------------------------


def test_every_operation_answers_as_described(walk: Walk, fmu_files: FmuFiles) -> None:
    device_token = _twins_and_devices(walk)
    _device_side(walk, device_token)
    _history(walk)
    _processors_and_fmus(walk, fmu_files("tingen").read_bytes())
    _gateway(walk)
    _connectors(walk)
    _users_and_tokens(walk)
    _system(walk)
    _library(walk)
    _federation(walk)
    _deployments(walk)
    _runs(walk)
    _cosims(walk, fmu_files)
    _remote_twins(walk)
    _workspaces(walk)
    _removals(walk)
    answered = {(m, p) for m, p, status in walk.contract.seen if 200 <= status < 300}
    assert walk.contract.operations() - answered == set()


def test_error_answers_are_the_problems_described(walk: Walk) -> None:
    w = walk
    w.ok(w.admin.post("/api/v1/apply", content=twin_doc(f"urn:{w.slug}", slug=w.slug),
                      headers=YAML_HEADERS))  # fmt: skip
    viewer = make_user(w.server, unique("viewer"))
    with w.client() as anonymous, w.client(viewer) as stranger:
        assert anonymous.get("/api/v1/twins").status_code == 401
        assert stranger.get(f"/api/v1/twins/{w.slug}/streams").status_code == 403
        assert stranger.get("/api/v1/users").status_code == 403
    assert w.admin.get("/api/v1/twins/no-such-twin").status_code == 404
    assert w.admin.get("/api/v1/twins", params={"limit": 0}).status_code == 422
    r = w.admin.post("/api/v1/apply", content=b"a: [", headers=YAML_HEADERS)
    assert r.status_code == 422 and r.json()["errors"][0]["line"] == 2
    w.ok(w.admin.post(f"/api/v1/twins/{w.slug}/devices", json={"name": "d"}), 201)
    assert w.admin.post(f"/api/v1/twins/{w.slug}/devices", json={"name": "d"}).status_code == 409
    r = w.admin.post(f"/api/v1/twins?slug={w.slug}", content=twin_doc(f"urn:{w.slug}"),
                     headers=YAML_HEADERS)  # fmt: skip
    assert r.status_code == 409
    errors = {status for _, _, status in w.contract.seen if status >= 400}
    assert {401, 403, 404, 409, 422} <= errors


# -- the walk, area by area ---------------------------------------------------------------------


def _twins_and_devices(w: Walk) -> str:
    features = [{"name": "Self", "apiAddress": w.server.url + "/", "keywords": ["contract"]}]
    doc = twin_doc(f"urn:{w.slug}", name="Contract", slug=w.slug, interface=INTERFACE,
                   features=features)  # fmt: skip
    w.ok(w.admin.post("/api/v1/apply", content=doc, headers=YAML_HEADERS))
    child = twin_doc(f"urn:{w.slug}-child", name="Child", relations=[("parent", f"urn:{w.slug}")])
    r = w.admin.post(f"/api/v1/twins?slug={w.slug}-child", content=child, headers=YAML_HEADERS)
    w.ok(r, 201)
    private = twin_doc(f"urn:{w.slug}-child", privacy="private", secret="s")
    w.ok(w.admin.put(f"/api/v1/twins/{w.slug}-child", content=private, headers=YAML_HEADERS))
    w.ok(w.admin.put(f"/api/v1/twins/{w.slug}?dry_run=true", content=doc, headers=YAML_HEADERS))
    w.ok(w.admin.get("/api/v1/twins", params={"limit": 1}))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/parts"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/parts/public"))
    w.admin.get(f"/api/v1/twins/{w.slug}/parts/public", params={"format": "yaml"})
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/relations"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}-child/relations", params={"direction": "up"}))
    for path, accept in (("", "text/html"), ("/index.yaml", "*/*"), ("/index.json", "*/*")):
        w.ok(w.admin.get(f"/twins/{w.slug}{path}", headers={"Accept": accept}))
    w.ok(w.admin.get(f"/twins/{w.slug}/index.html"))
    for fmt in ("wot-td", "dtdl", "aas-json"):  # the exports (api/exports.py)
        w.ok(w.admin.get(f"/twins/{w.slug}", params={"format": fmt}))
    w.ok(w.admin.get(f"/twins/{w.slug}/export.aasx"))
    w.ok(w.admin.get("/index.yaml"))
    w.ok(w.admin.get("/index.json"))
    w.ok(w.admin.get("/api/v1/search", params={"q": "contract"}))
    viewer = unique("viewer")
    make_user(w.server, viewer)
    w.ok(w.admin.put(f"/api/v1/twins/{w.slug}/roles/{viewer}", json={"role": "viewer"}))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/roles"))
    w.ok(w.admin.delete(f"/api/v1/twins/{w.slug}/roles/{viewer}"))
    made = w.ok(w.admin.post(f"/api/v1/twins/{w.slug}/devices", json={"name": "d1"}), 201)
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/devices"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/devices/d1"))
    return str(made["token"])


def _device_side(w: Walk, token: str) -> None:
    now = time.time_ns()
    batch = {"seq": 1, "samples": [{"time": now - 10**9, "values": {"x": 1.5, "label": "a"}},
                                   {"time": now, "values": {"x": 2}}]}  # fmt: skip
    command = {"name": "go", "args": {"v": 1}, "queue": True, "wait": False}
    sent = w.ok(w.admin.post(f"/api/v1/twins/{w.slug}/commands", json=command), 202)
    with w.client(token) as device:
        w.ok(device.get("/api/v1/device"))
        assert w.ok(device.post("/api/v1/device/samples", json=batch))["accepted"] == 2
        w.ok(device.post("/api/v1/device/properties", json={"properties": {"speed": 3}}))
        w.ok(device.get("/api/v1/device/properties"))
        assert w.ok(device.get("/api/v1/device/commands"))["commands"][0]["id"] == sent["id"]
        result = {"status": "succeeded", "result": {"ok": 1}}
        w.ok(device.post(f"/api/v1/device/commands/{sent['id']}/result", json=result))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/commands"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/commands/{sent['id']}"))
    w.ok(w.admin.get(f"/api/v1/twins/{w.slug}/devices/d1/properties"))
    w.ok(w.admin.patch(f"/api/v1/twins/{w.slug}/devices/d1/properties/desired", json={"speed": 5}))
    w.ok(w.admin.post(f"/api/v1/twins/{w.slug}/devices/d1/token"))


def _history(w: Walk) -> None:
    streams = f"/api/v1/twins/{w.slug}/streams"
    w.ok(w.admin.get(streams))
    for what, params in (
        ("latest", {}),
        ("samples", {"limit": 1}),
        ("aggregate", {"fn": "avg,sum,count,first"}),
        ("downsample", {"method": "lttb"}),
        ("export", {"format": "jsonl"}),
    ):
        w.ok(w.admin.get(f"{streams}/telemetry/{what}", params=params))


def _processors_and_fmus(w: Walk, fmu: bytes) -> None:
    base = f"/api/v1/twins/{w.slug}/processors"
    w.ok(w.admin.get("/api/v1/blueprints"))
    w.ok(w.admin.get("/api/v1/blueprints/expression"))
    spec = {"name": "p1", "blueprint": "expression", "params": {"outputs": {"y": "x * 2"}}}
    w.ok(w.admin.post(base, json=spec), 201)
    w.ok(w.admin.get(base))
    w.ok(w.admin.get(f"{base}/p1"))
    w.ok(w.admin.patch(f"{base}/p1", json={"params": {"outputs": {"y": "x * 3"}}}))
    for action in ("stop", "start", "restart"):
        w.ok(w.admin.post(f"{base}/p1/{action}"))
    w.ok(w.admin.get(f"{base}/p1/events"))
    w.ok(w.admin.get(f"{base}/p1/logs"))
    w.ok(w.admin.delete(f"{base}/p1"), 204)
    fmus = f"/api/v1/twins/{w.slug}/fmus"
    headers = {"Content-Type": "application/octet-stream"}
    w.ok(w.admin.put(f"{fmus}/Tingen.fmu", content=fmu, headers=headers), 201)
    w.ok(w.admin.get(fmus))
    w.ok(w.admin.get(f"{fmus}/Tingen.fmu"))
    w.ok(w.admin.delete(f"{fmus}/Tingen.fmu"), 204)


def _gateway(w: Walk) -> None:
    services = f"/api/v1/twins/{w.slug}/services"
    auth = {"method": "bearer", "token": "upstream-secret"}
    w.ok(w.admin.post(services, json={"name": "api", "base_url": w.server.url + "/", "auth": auth}),
         201)  # fmt: skip
    w.ok(w.admin.get(services))
    w.ok(w.admin.patch(f"{services}/api", json={"health_path": "/healthz"}))
    w.ok(w.admin.get(f"{services}/api/health"))
    with httpx.Client(base_url=w.server.url, headers=w.admin.headers) as plain:
        assert plain.get(f"/twins/{w.slug}/services/api/healthz").status_code == 200
    w.ok(w.admin.get(f"{services}/api"))  # with health and figures now
    w.ok(w.admin.get("/api/v1/gateway/audit", params={"twin": w.slug}))
    w.ok(w.admin.delete(f"{services}/api"))
    accounts = f"/api/v1/twins/{w.slug}/service-accounts"
    w.ok(w.admin.post(accounts, json={"name": "bot", "role": "viewer"}), 201)
    w.ok(w.admin.get(accounts))
    w.ok(w.admin.delete(f"{accounts}/bot"), 204)


def _connectors(w: Walk) -> None:
    base = f"/api/v1/twins/{w.slug}/connectors"
    w.ok(w.admin.get("/api/v1/connector-kinds"))
    body = {"name": "u1", "kind": "udp", "config": {"port": 0, "format": "json"}}
    w.ok(w.admin.post(base, json=body), 201)
    w.ok(w.admin.get(base))
    w.ok(w.admin.get(f"{base}/u1"))
    w.ok(w.admin.patch(f"{base}/u1", json={"enabled": False}))
    for action in ("start", "restart", "stop"):
        w.ok(w.admin.post(f"{base}/u1/{action}"))
    w.ok(w.admin.delete(f"{base}/u1"), 204)


def _users_and_tokens(w: Walk) -> None:
    name = unique("user")
    w.ok(w.admin.post("/api/v1/users", json={"username": name, "password": "a" * 12}), 201)
    w.ok(w.admin.get("/api/v1/users"))
    w.ok(w.admin.patch(f"/api/v1/users/{name}", json={"groups": ["lab"]}))
    w.ok(w.admin.post(f"/api/v1/users/{name}/tokens", json={"name": "script"}), 201)
    made = w.ok(w.admin.post("/api/v1/tokens", json={"name": "t", "expires_in_s": 600}), 201)
    w.ok(w.admin.get("/api/v1/tokens", params={"all": True}))
    w.ok(w.admin.delete(f"/api/v1/tokens/{made['id']}"))
    w.ok(w.admin.get("/api/v1/auth/me"))
    with w.client() as anonymous:
        login = {"username": name, "password": "a" * 12}
        session = w.ok(anonymous.post("/api/v1/auth/login", json=login))
    with w.client(session["token"]) as user:
        w.ok(user.post("/api/v1/auth/logout"))
    w.ok(w.admin.delete(f"/api/v1/users/{name}"))


def _system(w: Walk) -> None:
    w.ok(w.admin.get("/healthz"))
    w.ok(w.admin.get("/readyz"))
    w.ok(w.admin.get("/metrics"))
    w.ok(w.admin.get("/api/v1/mqtt"))


def _federation(w: Walk) -> None:
    peer = "/api/v1/federation/peers/peer.example.org"
    w.ok(w.admin.put(peer, json={"token": "a-token-of-the-peer"}))
    w.ok(w.admin.get("/api/v1/federation/peers"))
    w.ok(w.admin.delete(peer), 204)
    # This server's own twin, fetched as another instance's (loopback allowed here).
    w.ok(w.admin.get("/api/v1/resolve", params={"id": f"{w.server.url}/twins/{w.slug}"}))


def _library(w: Walk) -> None:
    base = f"/api/v1/library/me/data/{w.slug}"
    w.ok(w.admin.post(f"{base}/versions", params={"format": "file", "filename": "a.txt"},
                      content=b"a"), 201)  # fmt: skip
    w.ok(w.admin.get("/api/v1/library"))
    w.ok(w.admin.get(base))
    w.ok(w.admin.patch(base, json={"description": "contract"}))
    w.ok(w.admin.get(f"{base}/versions"))
    w.ok(w.admin.get(f"{base}/versions/latest"))
    w.ok(w.admin.get(f"{base}/versions/latest/archive"))
    w.ok(w.admin.get(f"{base}/versions/latest/files/a.txt"))
    w.ok(w.admin.put(f"{base}/tags/v1", json={"version": "latest"}))
    w.ok(w.admin.delete(f"{base}/tags/v1"), 204)
    w.ok(w.admin.delete(f"{base}/versions/latest"), 204)
    w.ok(w.admin.delete(base), 204)


def _deployments(w: Walk) -> None:
    name = f"{w.slug}-dep"
    package = "parameters: {type: object, properties: {n: {type: string, default: a}}}\n"
    w.ok(w.admin.post("/api/v1/library/me/twins/contract/versions",
                      params={"format": "file", "filename": "twin.yaml"},
                      content=package.encode()), 201)  # fmt: skip
    body = {"package": "contract", "name": name}
    w.ok(w.admin.post("/api/v1/deployments", params={"dry_run": True}, json=body))
    w.ok(w.admin.post("/api/v1/deployments", json={**body, "state": "planned"}), 201)
    w.ok(w.admin.post(f"/api/v1/deployments/{name}/create"))
    w.ok(w.admin.get("/api/v1/deployments"))
    w.ok(w.admin.get(f"/api/v1/deployments/{name}"))
    w.ok(w.admin.patch(f"/api/v1/deployments/{name}", json={"parameters": {"n": "b"}}))
    w.ok(w.admin.post(f"/api/v1/deployments/{name}/start"))
    w.ok(w.admin.post(f"/api/v1/deployments/{name}/stop"))
    w.ok(w.admin.post(f"/api/v1/deployments/{name}/terminate", json={"purge": True}))


def _cosims(w: Walk, fmu_files: FmuFiles) -> None:
    model = {
        "fmus": {"{a}": "msd_mass.fmu", "{b}": "msd_spring.fmu"},
        "connections": {"{a}.m.x1": ["{b}.s.x1"], "{a}.m.v1": ["{b}.s.v1"],
                        "{b}.s.fk": ["{a}.m.fk"]},
        "algorithm": {"type": "fixed-step", "size": 0.1}, "endTime": 1.0,
    }  # fmt: skip
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as archive:  # the multi-model beside its FMUs
        archive.writestr("mm.json", orjson.dumps(model))
        for name in ("msd_mass", "msd_spring"):
            archive.write(fmu_files(name), f"{name}.fmu")
    made = w.ok(w.admin.post("/api/v1/cosims", params={"twin": w.slug}, content=out.getvalue(),
                             headers={"Content-Type": "application/zip"}), 201)  # fmt: skip
    url = f"/api/v1/cosims/{made['id']}"
    w.ok(w.admin.get("/api/v1/cosims"))
    w.ok(w.admin.post(f"{url}/start", json={"mode": "batch"}))
    poll_until(lambda: w.ok(w.admin.get(url))["state"] != "running", "the cosim to end", 60)
    w.ok(w.admin.post(f"{url}/stop"))
    w.ok(w.admin.get(f"{url}/results.csv"))
    w.ok(w.admin.get(f"{url}/results", params={"max_points": 10}))
    w.ok(w.admin.delete(url), 204)


def _remote_twins(w: Walk) -> None:
    dt_id = f"urn:{w.slug}:remote"
    w.ok(w.admin.post("/api/v1/apply", content=twin_doc(dt_id, name="remote", slug=f"{w.slug}-r"),
                      headers=YAML_HEADERS))  # fmt: skip
    made = w.ok(w.admin.post("/api/v1/remote-twins/import", json={"url": w.server.url}))
    [twin] = [t for t in made["imported"] if t["dt_id"] == dt_id]
    url = f"/api/v1/remote-twins/{twin['id']}"
    w.ok(w.admin.get("/api/v1/remote-twins", params={"q": "remote"}))
    w.ok(w.admin.get(url))
    w.ok(w.admin.post(f"{url}/refresh"))
    w.ok(w.admin.delete(url), 204)


def _runs(w: Walk) -> None:
    name = f"{w.slug}-runs"
    package = tar_of({"twin.yaml": "description: runs\n", "lifecycle/analyze": "echo ok\n"})
    w.ok(w.admin.post("/api/v1/library/me/twins/contract-runs/versions",
                      params={"format": "tar"}, content=package), 201)  # fmt: skip
    w.ok(w.admin.post("/api/v1/deployments", json={"package": "contract-runs", "name": name}), 201)
    run = w.ok(w.admin.post(f"/api/v1/deployments/{name}/runs", json={"phase": "analyze"}), 202)
    poll_until(lambda: w.ok(w.admin.get(f"/api/v1/runs/{run['id']}"))["state"] == "succeeded",
               "the run to succeed")  # fmt: skip
    w.ok(w.admin.get(f"/api/v1/deployments/{name}/runs"))
    w.ok(w.admin.get(f"/api/v1/runs/{run['id']}/log"))
    w.ok(w.admin.post(f"/api/v1/runs/{run['id']}/cancel"))
    w.ok(w.admin.post(f"/api/v1/deployments/{name}/terminate", json={"purge": True}))


def _workspaces(w: Walk) -> None:
    """One real JupyterLab: started, shown, listed, stopped (a stopped one stops again)."""
    me = w.ok(w.admin.post("/api/v1/workspaces/me"))
    w.ok(w.admin.get("/api/v1/workspaces/me"))
    w.ok(w.admin.get("/api/v1/workspaces"))
    w.ok(w.admin.delete("/api/v1/workspaces/me"), 204)
    w.ok(w.admin.delete(f"/api/v1/workspaces/{me['user']}"), 204)


def _removals(w: Walk) -> None:
    w.ok(w.admin.delete(f"/api/v1/twins/{w.slug}/devices/d1"))
    w.ok(w.admin.delete(f"/api/v1/twins/{w.slug}-child/parts/private"))
    w.ok(w.admin.delete(f"/api/v1/twins/{w.slug}", params={"cascade": True}))


def test_the_web_apps_api_types_are_generated_from_this_description() -> None:
    """ui/src/api/openapi.ts is what openapi-typescript makes of the description now (written
    by `python -m twinlink.openapi`, without a server): a change to a route's models
    without `make ui-types` fails here."""
    node = shutil.which("node")
    assert node, "Node.js 20+ is needed (make test installs it)"
    assert (UI / "node_modules" / "openapi-typescript").is_dir(), "run make test (npm install)"
    run = subprocess.run(
        [node, "scripts/api-types.mjs", "--check"],
        cwd=UI,
        env={**os.environ, "TWINLINK_PYTHON": sys.executable},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr or run.stdout
