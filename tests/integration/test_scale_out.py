"""One node on PostgreSQL and Kafka (TWINLINK_STORE_URL, TWINLINK_BUS_URL; docs/scale-out.md):
a real `twinlink up` process on a real database and broker makes the first admin, takes a
document and a device's batch over HTTP, reads the history back, and keeps all of it across a
restart, even on an empty data dir (nothing of it is in SQLite)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import Cluster, cluster
from tests.integration._util import get_doc, make_user, poll_until

pytestmark = pytest.mark.integration

T0 = 1_700_000_000 * 10**9
ROWS = [
    {"time": T0 + i * 10**6, "values": {"x": i * 0.5, "n": i, "mode": "run"}} for i in range(50)
]


@pytest.fixture(scope="module")
def shared(postgres_cluster: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    with cluster(postgres_cluster, kafka) as c:
        yield c


def samples(server: Server, token: str, slug: str) -> list[dict[str, Any]]:
    with server.client(token) as c:
        r = c.get(f"/api/v1/twins/{slug}/streams/telemetry/samples", params={"limit": 1000})
    assert r.status_code == 200, r.text
    return r.json()["rows"]  # type: ignore[no-any-return]


def post(server: Server, device: str, seq: int, rows: list[dict[str, Any]]) -> dict[str, Any]:
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": rows})
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_a_node_keeps_everything_in_postgresql_across_a_restart(
    shared: Cluster, tmp_path: Path
) -> None:
    node = shared.start(tmp_path / "first", TWINLINK_LOG_LEVEL="info")
    try:
        # the ready line names the store without its password, and nothing else shows it
        ready = poll_until(
            lambda: [line for line in node.output if '"event":"ready"' in line], "the ready line"
        )
        assert ":***@127.0.0.1" in ready[0] and "kafka://127.0.0.1" in ready[0], ready
        with node.admin as admin:  # the first admin, made with the preset token
            assert admin.get("/api/v1/auth/me").json()["username"] == "admin"
        viewer = make_user(node, "viewer")
        slug, [device] = device_twin(node)
        with node.admin as admin:
            r = admin.put(f"/api/v1/twins/{slug}/roles/viewer", json={"role": "viewer"})
            assert r.status_code == 200, r.text
        ack = post(node, device, 1, ROWS)
        assert (ack["accepted"], ack["duplicate"]) == (50, False)
        assert samples(node, viewer, slug) == ROWS
    finally:
        stop_server(node)
    # what the node keeps went to PostgreSQL, not to SQLite files in its data dir
    assert not (tmp_path / "first" / "twinlink.sqlite3").exists()
    assert not (tmp_path / "first" / "history.db").exists()
    assert shared.fetchval("SELECT count(*) FROM twins WHERE slug = $1", slug) == 1
    assert shared.password not in node.log()

    # the same node again, on an empty data dir: every part of the state is still there
    again = shared.start(tmp_path / "second", token=node.admin_token)
    try:
        with again.admin as admin:
            assert get_doc(admin, slug)["name"] == "Rig"
        assert samples(again, viewer, slug) == ROWS  # the viewer's session token still works
        resent = post(again, device, 1, ROWS)  # the device's token too; (device, seq) is kept
        assert (resent["accepted"], resent["duplicate"]) == (0, True)
        more = [{"time": T0 + 10**9, "values": {"x": 99.5, "n": 99, "mode": "stop"}}]
        assert post(again, device, 2, more)["accepted"] == 1
        assert samples(again, viewer, slug) == ROWS + more
        assert "created the first admin" not in again.log()  # not made a second time
    finally:
        stop_server(again)
