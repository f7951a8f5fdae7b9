"""Two `twinlink up` nodes sharing one PostgreSQL database and one Kafka broker (docs/scale-out.md):
what is made on one is there on the other, a device's batch sent to one is seen live by a
browser on the other and stored once, and a change on one node reaches the other's caches
(tokens, roles, twins) at once instead of when they happen to expire."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import orjson
import pytest
from websockets.sync.client import ClientConnection, connect

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin, ws_url
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import cluster
from tests.integration._util import (
    apply,
    assert_problem,
    get_doc,
    make_user,
    poll_until,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

T0 = 1_700_000_000 * 10**9
# How soon the other node must follow a change: far below the token cache's 30 s, far above
# the bus's few milliseconds between nodes on a loaded machine.
FOLLOWS_S = 10.0
TIMEOUT_S = 30


@dataclass
class Nodes:
    a: Server
    b: Server


@pytest.fixture(scope="module")
def nodes(
    postgres_cluster: PostgresCluster,
    kafka: KafkaBroker,
    tmp_path_factory: pytest.TempPathFactory,
) -> Iterator[Nodes]:
    with cluster(postgres_cluster, kafka) as shared:
        a = shared.start(tmp_path_factory.mktemp("node-a"))
        try:
            b = shared.start(tmp_path_factory.mktemp("node-b"), token=a.admin_token)
            try:
                yield Nodes(a, b)
            finally:
                stop_server(b)
        finally:
            stop_server(a)


def post(server: Server, device: str, seq: int, rows: list[dict[str, Any]]) -> dict[str, Any]:
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": rows})
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def samples(server: Server, token: str, slug: str) -> list[dict[str, Any]]:
    with server.client(token) as c:
        r = c.get(f"/api/v1/twins/{slug}/streams/telemetry/samples", params={"limit": 1000})
    assert r.status_code == 200, r.text
    return r.json()["rows"]  # type: ignore[no-any-return]


@contextmanager
def watching(server: Server, token: str, slug: str) -> Iterator[ClientConnection]:
    """A live client subscribed to every stream of `slug`."""
    headers = {"Authorization": f"Bearer {token}"}
    url = ws_url(server, "/api/v1/live")
    with connect(url, additional_headers=headers, open_timeout=TIMEOUT_S) as ws:
        assert orjson.loads(ws.recv(timeout=TIMEOUT_S))["type"] == "welcome"
        ws.send(orjson.dumps({"op": "subscribe", "id": "s", "twin": slug}).decode())
        answer = orjson.loads(ws.recv(timeout=TIMEOUT_S))
        assert answer["type"] == "subscribed", answer
        yield ws


def status(server: Server, token: str, path: str) -> int:
    with server.client(token) as c:
        return c.get(path).status_code


# -- what one node makes, the other has ------------------------------------------------------


def test_a_token_made_on_one_node_works_on_the_other(nodes: Nodes) -> None:
    name = unique("user")
    token = make_user(nodes.a, name)  # a login session, made on A
    with nodes.b.client(token) as c:
        assert c.get("/api/v1/auth/me").json()["username"] == name
        made = c.post("/api/v1/tokens", json={"name": "made on b"})
        assert made.status_code == 201, made.text
    with nodes.a.client(made.json()["token"]) as c:
        assert c.get("/api/v1/auth/me").json()["username"] == name


def test_a_twin_applied_on_one_node_is_read_on_the_other(nodes: Nodes) -> None:
    slug = unique("twin")
    with nodes.a.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Made on A", slug=slug))
    with nodes.b.admin as admin:
        assert get_doc(admin, slug)["name"] == "Made on A"
        found = admin.get("/api/v1/search", params={"q": "made"}).json()
    assert slug in [hit["slug"] for hit in found["hits"]]


def test_a_batch_sent_to_one_node_is_seen_live_on_the_other_and_stored_once(
    nodes: Nodes,
) -> None:
    slug, [device] = device_twin(nodes.a)
    rows = [{"time": T0 + i * 10**6, "values": {"x": i, "y": i / 4}} for i in range(20)]
    with watching(nodes.a, nodes.a.admin_token, slug) as ws:
        ack = post(nodes.b, device, 1, rows)  # the device is on node B
        assert (ack["accepted"], ack["duplicate"]) == (20, False)
        message = orjson.loads(ws.recv(timeout=TIMEOUT_S))  # through Kafka, on node A
    assert message["type"] == "samples" and message["samples"] == rows
    assert samples(nodes.a, nodes.a.admin_token, slug) == rows  # once, not once per node
    assert samples(nodes.b, nodes.b.admin_token, slug) == rows
    resent = post(nodes.a, device, 1, rows)  # the same batch again, to the other node
    assert (resent["accepted"], resent["duplicate"]) == (0, True)
    assert samples(nodes.b, nodes.b.admin_token, slug) == rows


# -- a change on one node reaches the other's caches -----------------------------------------


def test_a_token_revoked_on_one_node_is_refused_on_the_other(nodes: Nodes) -> None:
    owner = make_user(nodes.a, unique("rev"))
    with nodes.a.client(owner) as c:
        made = c.post("/api/v1/tokens", json={"name": "short-lived"}).json()
    assert status(nodes.b, made["token"], "/api/v1/auth/me") == 200  # B has it cached now
    with nodes.a.client(owner) as c:
        assert c.delete(f"/api/v1/tokens/{made['id']}").status_code == 200
    poll_until(
        lambda: status(nodes.b, made["token"], "/api/v1/auth/me") == 401,
        "node B to refuse the token revoked on node A",
        FOLLOWS_S,
    )
    with nodes.b.client(made["token"]) as c:
        assert_problem(c.get("/api/v1/twins"), 401)


def test_a_role_taken_away_on_one_node_is_gone_on_the_other(nodes: Nodes) -> None:
    name = unique("viewer")
    viewer = make_user(nodes.a, name)
    slug, _ = device_twin(nodes.a)
    history = f"/api/v1/twins/{slug}/streams"
    with nodes.a.admin as admin:
        assert admin.put(f"/api/v1/twins/{slug}/roles/{name}", json={"role": "viewer"}).is_success
    assert status(nodes.b, viewer, history) == 200  # B has the role cached now
    with nodes.a.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}/roles/{name}").is_success
    assert status(nodes.a, viewer, history) == 403  # the history needs a role
    poll_until(
        lambda: status(nodes.b, viewer, history) == 403,
        "node B to forget the role taken away on node A",
        FOLLOWS_S,
    )


def test_a_twin_changed_on_one_node_is_read_changed_on_the_other(nodes: Nodes) -> None:
    slug = unique("twin")
    with nodes.a.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Before", slug=slug))
    with nodes.b.admin as admin:
        assert get_doc(admin, slug)["name"] == "Before"  # B has the twin cached now
    with nodes.a.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="After", slug=slug))

    def name_on_b() -> str:
        with nodes.b.admin as admin:
            return str(get_doc(admin, slug)["name"])

    poll_until(lambda: name_on_b() == "After", "node B to read the twin changed on A", FOLLOWS_S)


def test_a_twin_deleted_on_one_node_is_gone_on_the_other(nodes: Nodes) -> None:
    slug, [device] = device_twin(nodes.a)
    post(nodes.b, device, 1, [{"time": T0, "values": {"x": 1}}])  # B has the twin cached
    with nodes.a.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}").is_success
        assert_problem(admin.get(f"/api/v1/twins/{slug}/streams"), 404)
    poll_until(
        lambda: status(nodes.b, nodes.b.admin_token, f"/api/v1/twins/{slug}/streams") == 404,
        "node B to forget the twin deleted on A",
        FOLLOWS_S,
    )


def test_a_twins_interface_changed_on_one_node_checks_the_batches_of_the_other(
    nodes: Nodes,
) -> None:
    def interface(top: float) -> dict[str, Any]:
        return {"signals": [{"name": "angle", "type": "number", "min": 0, "max": top}]}

    slug, [device] = device_twin(nodes.a, interface(1))
    seq = iter(range(1, 1000))
    assert post(nodes.b, device, next(seq), [{"values": {"angle": 5}}])["rejected_count"] == 1
    with nodes.a.admin as admin:  # B has the rules cached; A allows up to 10 now
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, interface=interface(10)))
    poll_until(
        lambda: post(nodes.b, device, next(seq), [{"values": {"angle": 5}}])["accepted"] == 1,
        "node B to check batches with the interface changed on A",
        FOLLOWS_S,
    )
