"""The external MQTT mode on two nodes (docs/scale-out.md): one node holds the broker session
(its lease), the other stands by; when the holder is killed the other takes the session over
with the same client id, and what devices sent meanwhile (QoS 1, kept by the broker for the
lasting session) is stored, each batch once."""

from __future__ import annotations

import asyncio
import os
import signal
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import orjson
import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._mqtt import Mosquitto, mosquitto_pub, require_mosquitto
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import Cluster, cluster
from tests.integration._util import poll_until

pytestmark = pytest.mark.integration

USERS = {"twinlink": "platform-secret", "rig": "rig-secret"}
T0 = 1_700_000_000 * 10**9
TAKEOVER_S = 60  # the lease's 10 s TTL and a round, on a loaded machine


@pytest.fixture
def broker(tmp_path: Path) -> Iterator[Mosquitto]:
    require_mosquitto()
    mosquitto = Mosquitto(tmp_path, USERS)
    asyncio.run(mosquitto.start())
    try:
        yield mosquitto
    finally:
        asyncio.run(mosquitto.stop())


@pytest.fixture
def shared(postgres_cluster: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    with cluster(postgres_cluster, kafka) as shared:
        yield shared


def external(broker: Mosquitto) -> dict[str, str]:
    return {"TWINLINK_MQTT_MODE": "external", "TWINLINK_MQTT_BROKER_URL": broker.url,
            "TWINLINK_MQTT_USERNAME": "twinlink",
            "TWINLINK_MQTT_PASSWORD": USERS["twinlink"]}  # fmt: skip


def state(node: Server) -> str:
    with node.admin as admin:
        r = admin.get("/api/v1/mqtt")
    assert r.status_code == 200, r.text
    return str(r.json()["state"])


def publish(broker: Mosquitto, slug: str, seq: int) -> None:
    batch = {"seq": seq, "samples": [{"time": T0 + seq, "values": {"x": seq}}]}
    rc, out = asyncio.run(mosquitto_pub(
        broker.port, "-u", "rig", "-P", USERS["rig"], "-q", "1",
        "-t", f"twinlink/{slug}/dev0/telemetry", "-m", orjson.dumps(batch).decode(),
    ))  # fmt: skip
    assert rc == 0, out


def stored(node: Server, slug: str) -> list[Any]:
    with node.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/streams/telemetry/samples", params={"limit": 100})
    assert r.status_code == 200, r.text
    return sorted(row["values"]["x"] for row in r.json()["rows"])


def test_one_node_holds_the_broker_session_and_another_takes_it_over(
    shared: Cluster, broker: Mosquitto, tmp_path: Path
) -> None:
    a = shared.start(tmp_path / "a", **external(broker))
    b: Server | None = None
    try:
        b = shared.start(tmp_path / "b", token=a.admin_token, **external(broker))
        assert (state(a), state(b)) == ("connected", "standby")
        slug, _ = device_twin(a)
        publish(broker, slug, 1)
        poll_until(lambda: stored(b, slug) == [1], "the first batch stored")

        os.kill(a.process.pid, signal.SIGKILL)  # the holder dies without a word
        a.process.wait()
        for seq in (2, 3):  # while no node holds the session: the broker keeps them
            publish(broker, slug, seq)
        poll_until(lambda: state(b) == "connected", "B to take the session", TAKEOVER_S)
        poll_until(lambda: stored(b, slug) == [1, 2, 3], "what was sent meanwhile, stored once")
        publish(broker, slug, 4)
        poll_until(lambda: stored(b, slug) == [1, 2, 3, 4], "the next batch")
    finally:
        for node in (a, b):
            if node is not None:
                stop_server(node)
