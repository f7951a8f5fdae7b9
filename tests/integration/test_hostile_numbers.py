"""Hostile numbers (issue 13, items 2 and 3). Every numeric parameter of the API has a
declared range in /openapi.json; huge, negative, fractional, non-finite and beyond-64-bit
values get a problem+json 4xx and never a 500 on any route, found by walking the OpenAPI
document of a real server (and the schemas of connector configs and blueprint parameters);
and an integer beyond 64 bits is refused with the one message (`jsontext.int64_problem`) on
every transport, never stored rounded to a float."""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._hostile import (
    BIG_INTS,
    BODY_VALUES,
    HOLE,
    QUERY_VALUES,
    TIME_VALUES,
    Operation,
    body_schema,
    fill_path,
    has_range,
    is_free_form,
    numeric_fields,
    numeric_parameters,
    operations,
    schema_at,
    schema_numbers,
    time_parameters,
    with_value,
)
from tests.integration._util import PROBLEM, apply, twin_doc, unique

pytestmark = pytest.mark.integration

# Plain real numbers with no natural bound: a scale and an offset may be any finite value
# (the exact JSON reader refuses NaN and infinities before they get here).
UNBOUNDED = {("InputMap", "scale"), ("InputMap", "offset")}
TIMED = ("_s", "_ms", "_ns", "_hz", "_samples")  # durations, rates and counts of samples

# A body that is valid but for the number under test, for each route whose body model has
# numeric fields.
MODEL_BASES: dict[tuple[str, str], dict[str, Any]] = {
    ("POST", "/api/v1/tokens"): {"name": "fuzz"},
    ("POST", "/api/v1/users/{username}/tokens"): {"name": "fuzz"},
    ("POST", "/api/v1/twins/{slug}/commands"): {"name": "go", "wait": False},
    ("POST", "/api/v1/twins/{slug}/processors"): {
        "name": "fuzz-new", "blueprint": "expression", "enabled": False,
        "params": {"outputs": {"y": "x"}},
    },
}  # fmt: skip

# Bodies whose numbers other tests check: a device's batch, whose `seq` out of range has its
# own message over HTTP and whose samples are refused one by one in the ack
# (test_big_integers.py, tests/unit/test_samples_batch.py).
CHECKED_ELSEWHERE = {("POST", "/api/v1/device/samples")}

# Numbers put into free-form bodies: each seed is sent once per value at HOLE.
SEEDS: dict[tuple[str, str], list[str]] = {
    ("POST", "/api/v1/twins"): [
        '{"version": "1.0", "id": "urn:fuzz-doc", "name": "F", "extra": {"n": @}}',
        '{"version": "1.0", "id": "urn:fuzz-doc", "name": "F", "createdMachine": @}',
    ],
    ("POST", "/api/v1/apply"): [
        '{"version": "1.0", "id": "urn:fuzz-doc", "name": "F",'
        ' "features": [{"name": "f", "n": @}]}',
    ],
    ("PUT", "/api/v1/twins/{slug}"): [
        '{"version": "1.0", "id": "urn:{slug}", "name": "Fuzz", "slug": "{slug}", "n": @}',
    ],
    ("POST", "/api/v1/device/commands/{command_id}/result"): [
        '{"status": "succeeded", "result": {"n": [@]}}',
    ],
    ("PATCH", "/api/v1/twins/{slug}/devices/{device}/properties/desired"): ['{"v": @}'],
    ("POST", "/api/v1/device/properties"): ['{"properties": {"v": @}}'],
    ("PATCH", "/api/v1/twins/{slug}/processors/{name}"): [
        '{"batch_timeout_s": @}', '{"memory_limit_mb": @}', '{"rates": {"max_batch": @}}',
        '{"rates": {"min_input_spacing_s": @}}', '{"params": {"outputs": {"y": "x"}, "k": @}}',
        '{"inputs": {"x": {"signal": "x", "scale": @}}}',
    ],
    ("POST", "/api/v1/twins/{slug}/services"): [
        '{"name": "fuzz-svc", "base_url": "http://127.0.0.1:9", "limits": {"timeout_s": @}}',
        '{"name": "fuzz-svc", "base_url": "http://127.0.0.1:9", "limits": {"max_body_mb": @}}',
        '{"name": "fuzz-svc", "base_url": "http://127.0.0.1:9", "auth": {"method": "oauth2_client",'
        ' "token_url": "http://127.0.0.1:9/t", "client_id": "c", "client_secret": "s",'
        ' "body": {"n": @}}}',
    ],
    ("PATCH", "/api/v1/twins/{slug}/services/{name}"): [
        '{"limits": {"connect_timeout_s": @}}', '{"description": @}',
    ],
    ("POST", "/api/v1/twins/{slug}/service-accounts"): ['{"name": "fuzz-sa", "role": @}'],
    ("POST", "/api/v1/twins/{slug}/connectors"): [
        '{"name": "fuzz-c", "kind": "udp", "enabled": false, "config": {"port": @}}',
    ],
    ("PATCH", "/api/v1/twins/{slug}/connectors/{name}"): [
        '{"config": {"batch_window_ms": @}}', '{"enabled": @}',
    ],
}  # fmt: skip

# Valid parameters of each blueprint and config of each connector kind, for the numbers of
# their schemas (from /api/v1/blueprints and /api/v1/connector-kinds) to be tried one by one.
COSIM = {"type": "fixed-step", "size": 0.1}
BLUEPRINT_BASES: dict[str, dict[str, Any]] = {
    "bandpass": {"signals": ["x"], "sample_rate_hz": 100, "low_hz": 1, "high_hz": 10},
    "bandstop": {"signals": ["x"], "sample_rate_hz": 100, "low_hz": 1, "high_hz": 10},
    "highpass": {"signals": ["x"], "sample_rate_hz": 100, "cutoff_hz": 10},
    "lowpass": {"signals": ["x"], "sample_rate_hz": 100, "cutoff_hz": 10},
    "complementary": {"rate": "r", "angle": "a"},
    "cosim": {"system": {"instances": {"a": "A.fmu"}, "algorithm": COSIM}, "outputs": {"y": "a.x"}},
    "expression": {"outputs": {"y": "x"}},
    "fft": {"signals": ["x"], "sample_rate_hz": 100},
    "fmu": {"fmu": "none.fmu"},
    "trigger": {"signal": "x", "high": 1},
    "window": {"signals": ["x"]},
}
CONNECTOR_BASES: dict[str, dict[str, Any]] = {
    "udp": {"port": 0, "format": "json"},
    "opcua": {"url": "opc.tcp://127.0.0.1:9/x", "signals": [{"node": "ns=2;i=1", "signal": "s"}]},
}


@dataclass
class Target:
    """What the fuzzed routes act on: a twin with a device, a service, a processor and a
    connector, all the admin's."""

    slug: str
    device_token: str
    names: dict[str, str]


@pytest.fixture(scope="module")
def target(server: Server) -> Target:
    slug = unique("fuzz")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Fuzz", slug=slug))
        made = [
            admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "dev"}),
            admin.post(f"/api/v1/twins/{slug}/services",
                       json={"name": "svc", "base_url": "http://127.0.0.1:9"}),
            admin.post(f"/api/v1/twins/{slug}/processors", json={
                "name": "proc", "blueprint": "expression", "enabled": False,
                "params": {"outputs": {"y": "x"}}}),
            admin.post(f"/api/v1/twins/{slug}/connectors", json={
                "name": "udp", "kind": "udp", "enabled": False, "config": CONNECTOR_BASES["udp"]}),
        ]  # fmt: skip
    for r in made:
        assert r.status_code == 201, r.text
    now = time.time_ns()
    with server.client(made[0].json()["token"]) as device:
        rows = [{"time": now - i * 10**9, "values": {"x": i, "y": 0.5}} for i in range(50)]
        r = device.post("/api/v1/device/samples", json={"seq": 1, "samples": rows})
        assert r.status_code == 200 and r.json()["accepted"] == 50, r.text
    names = {
        "slug": slug, "device": "dev", "stream": "telemetry", "username": "admin",
        "command_id": "nothing", "services/name": "svc", "processors/name": "proc",
        "connectors/name": "udp", "fmus/name": "none.fmu", "blueprints/name": "expression",
        "service-accounts/name": "nobody",
    }  # fmt: skip
    return Target(slug, made[0].json()["token"], names)


@pytest.fixture(scope="module")
def openapi(server: Server) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get("/openapi.json")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


class Fuzzer:
    """Sends requests and keeps every answer that is a 5xx or not problem+json, or that takes
    an integer beyond 64 bits without the one message for it."""

    def __init__(self, server: Server, target: Target) -> None:
        self.server, self.target = server, target
        self.failures: list[str] = []
        self.clients = {
            "admin": server.client(server.admin_token),
            "device": server.client(target.device_token),
        }

    def send(self, method: str, path: str, *, params: Any = None, body: str | None = None) -> None:
        who = "device" if path.startswith("/api/v1/device/") else "admin"
        headers = {"Content-Type": "application/json"} if body is not None else {}
        shown = f"{method} {path} {params or ''}{(body or '')[:120]}"
        for attempt in (1, 2):
            try:
                r = self.clients[who].request(
                    method, path, params=params, content=body, headers=headers
                )
                break
            except httpx.TransportError as err:
                # The server closes a connection after a 500: the next request on it fails
                # for that one. Once more on a new connection, to blame the right request.
                token = self.clients[who].headers["authorization"].removeprefix("Bearer ")
                self.clients[who].close()
                self.clients[who] = self.server.client(token)
                if attempt == 2:
                    self.failures.append(f"{shown} -> {err!r}")
                    return
        if r.status_code >= 500 or (
            r.status_code >= 400 and not r.headers["content-type"].startswith(PROBLEM)
        ):
            self.failures.append(f"{shown} -> {r.status_code} {r.text[:200]}")
        elif (
            body is not None
            and any(big in body for big in BIG_INTS)
            and (r.status_code != 422 or "does not fit in 64 bits" not in r.text)
        ):
            # Beyond 64 bits: refused with the one message (not rounded, not a type error).
            self.failures.append(f"{shown} -> {r.status_code} {r.text[:200]} (want int64)")
        if r.status_code == 201 and method == "POST" and body is not None:
            self._remove(path, json.loads(body.replace(HOLE, "0")).get("name"))

    def _remove(self, path: str, name: Any) -> None:
        """Something was made with a value that happened to be valid: delete it, so the next
        value meets no name conflict (tokens and documents just stay)."""
        if isinstance(name, str) and path.rsplit("/", 1)[-1] in ("services", "processors",
                                                                 "connectors"):  # fmt: skip
            self.clients["admin"].delete(f"{path}/{name}")

    def close(self) -> None:
        for client in self.clients.values():
            client.close()


@pytest.fixture
def fuzzer(server: Server, target: Target) -> Iterator[Fuzzer]:
    fuzzing = Fuzzer(server, target)
    try:
        yield fuzzing
    finally:
        fuzzing.close()


def _concrete(op: Operation, target: Target) -> str:
    return fill_path(op.path, target.names)


def test_every_numeric_parameter_declares_a_range(openapi: dict[str, Any]) -> None:
    unranged = []
    for op in operations(openapi):
        for where, name, schema in numeric_parameters(openapi, op):
            if not has_range(schema):
                unranged.append(f"{op.method} {op.path} {where} {name}")
        body = body_schema(openapi, op)
        for path, schema, model in numeric_fields(openapi, body or {}):
            if not has_range(schema) and (model, path[-1]) not in UNBOUNDED:
                unranged.append(f"{op.method} {op.path} body {'.'.join(path)} ({model})")
    assert unranged == [], "numbers without a declared minimum and maximum:\n" + "\n".join(unranged)


def test_blueprint_integers_durations_and_rates_declare_a_range(server: Server) -> None:
    # Thresholds (a trigger's high, low, clear_at, rate_limit) are plain reals: any finite value.
    with server.admin as admin:
        blueprints = admin.get("/api/v1/blueprints").json()["blueprints"]
    unranged = []
    for blueprint in blueprints:
        schema = blueprint["params_schema"]
        for path in schema_numbers(schema, schema, BLUEPRINT_BASES[blueprint["name"]]):
            field = schema_at(schema, path)
            name = str(path[-1])
            if (field.get("type") == "integer" or name.endswith(TIMED)) and not has_range(field):
                unranged.append(f"{blueprint['name']}: {'.'.join(map(str, path))}")
    assert unranged == [], "blueprint parameters without a minimum and maximum: " + ", ".join(
        unranged
    )


def test_connector_config_numbers_declare_a_range(server: Server) -> None:
    with server.admin as admin:
        kinds = admin.get("/api/v1/connector-kinds").json()["kinds"]
    unranged = []
    for kind in kinds:
        schema = kind["schema"]
        for path in schema_numbers(schema, schema, CONNECTOR_BASES[kind["kind"]]):
            if not has_range(schema_at(schema, path)):
                unranged.append(f"{kind['kind']}: {'.'.join(map(str, path))}")
    assert unranged == [], "connector settings without a minimum and maximum: " + ", ".join(
        unranged
    )


def test_extreme_path_and_query_numbers_are_refused_clearly(
    openapi: dict[str, Any], target: Target, fuzzer: Fuzzer
) -> None:
    for op in operations(openapi):
        path = _concrete(op, target)
        for where, name, _ in numeric_parameters(openapi, op):
            for value in QUERY_VALUES:
                if where == "path":
                    fuzzer.send(op.method, path.replace(f"{{{name}}}", value))
                else:
                    fuzzer.send(op.method, path, params={name: value})
    assert fuzzer.failures == [], "\n".join(fuzzer.failures)


def test_extreme_times_and_durations_are_refused_clearly(
    openapi: dict[str, Any], target: Target, fuzzer: Fuzzer
) -> None:
    for op in operations(openapi):
        path = _concrete(op, target)
        for name in time_parameters(op):
            for value in TIME_VALUES:
                fuzzer.send(op.method, path, params={name: value})
    assert fuzzer.failures == [], "\n".join(fuzzer.failures)


def test_extreme_numbers_in_json_bodies_are_refused_clearly(
    openapi: dict[str, Any], target: Target, fuzzer: Fuzzer
) -> None:
    uncovered = []
    for op in operations(openapi):
        body = body_schema(openapi, op)
        if body is None or (op.method, op.path) in CHECKED_ELSEWHERE:
            continue
        path = _concrete(op, target)
        key = (op.method, op.path)
        fields = list(numeric_fields(openapi, body))
        if fields and key not in MODEL_BASES:
            uncovered.append(f"{key}: add a valid body to MODEL_BASES")
        for field_path, _, _ in fields if key in MODEL_BASES else []:
            text = with_value(MODEL_BASES[key], field_path)
            for value in BODY_VALUES:
                fuzzer.send(op.method, path, body=text.replace(HOLE, value))
        if is_free_form(body) or key in SEEDS:
            if key not in SEEDS:
                uncovered.append(f"{key}: a free-form body; add seeds to SEEDS")
            for seed in SEEDS.get(key, []):
                seed = seed.replace("{slug}", target.slug)
                for value in BODY_VALUES:
                    fuzzer.send(op.method, path, body=seed.replace(HOLE, value))
    assert uncovered == [], "\n".join(uncovered)
    assert fuzzer.failures == [], "\n".join(fuzzer.failures)


def test_extreme_numbers_in_blueprint_parameters_and_connector_configs(
    server: Server, target: Target, fuzzer: Fuzzer
) -> None:
    with server.admin as admin:
        blueprints = admin.get("/api/v1/blueprints").json()["blueprints"]
        kinds = admin.get("/api/v1/connector-kinds").json()["kinds"]
    missing = [b["name"] for b in blueprints if b["name"] not in BLUEPRINT_BASES]
    missing += [k["kind"] for k in kinds if k["kind"] not in CONNECTOR_BASES]
    assert missing == [], f"add a valid base to BLUEPRINT_BASES or CONNECTOR_BASES: {missing}"
    for blueprint in blueprints:
        base = {"name": "fuzz-bp", "blueprint": blueprint["name"], "enabled": False,
                "params": BLUEPRINT_BASES[blueprint["name"]]}  # fmt: skip
        schema = blueprint["params_schema"]
        for path in schema_numbers(schema, schema, base["params"]):
            text = with_value(base, ("params", *path))
            for value in BODY_VALUES:
                fuzzer.send(
                    "POST",
                    f"/api/v1/twins/{target.slug}/processors",
                    body=text.replace(HOLE, value),
                )
    for kind in kinds:
        base = {"name": "fuzz-c", "kind": kind["kind"], "enabled": False,
                "config": CONNECTOR_BASES[kind["kind"]]}  # fmt: skip
        schema = kind["schema"]
        for path in schema_numbers(schema, schema, base["config"]):
            text = with_value(base, ("config", *path))
            for value in BODY_VALUES:
                fuzzer.send(
                    "POST",
                    f"/api/v1/twins/{target.slug}/connectors",
                    body=text.replace(HOLE, value),
                )
    assert fuzzer.failures == [], "\n".join(fuzzer.failures)
