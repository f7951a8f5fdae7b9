"""`twinlink up --workers 2` on the test PostgreSQL and Kafka (docs/scale-out.md): two server
processes behind one HTTP port and one MQTT port; a worker that dies is started again while
the other serves; a stop ends them all. Which worker takes a connection is the kernel's
choice, so the tests kill one to know which serves."""

from __future__ import annotations

import asyncio
import os
import signal
from collections.abc import Iterator
from pathlib import Path

import orjson
import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._mqtt import mosquitto_pub, require_mosquitto
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import Cluster, cluster
from tests.integration._util import poll_until

pytestmark = pytest.mark.integration

T0 = 1_700_000_000 * 10**9


@pytest.fixture(scope="module")
def shared(postgres_cluster: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    with cluster(postgres_cluster, kafka) as shared:
        yield shared


def workers_of(server: Server) -> list[int]:
    """The pids of the parent's children (its workers)."""
    pid = server.process.pid
    children = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    return sorted(int(c) for c in children)


def alive(pid: int) -> bool:
    """Until its parent reaped it. Not "until it is a zombie": the main thread of a killed
    process is a zombie while its other threads still end, its sockets still open (a
    connection the kernel queued on its listening socket meanwhile is then reset)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def send(server: Server, device: str, seq: int) -> None:
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": [
            {"time": T0 + seq, "values": {"x": seq}}]})  # fmt: skip
    assert r.status_code == 200, r.text
    assert r.json()["accepted"] == 1


def stored(server: Server, slug: str) -> list[int]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/streams/telemetry/samples", params={"limit": 100})
    assert r.status_code == 200, r.text
    return sorted(row["values"]["x"] for row in r.json()["rows"])


def kill_and_wait_for_new(server: Server, victim: int) -> int:
    """SIGKILL one worker; the pid of the worker the parent starts in its place."""
    os.kill(victim, signal.SIGKILL)
    before = set(workers_of(server)) - {victim}
    new = poll_until(
        lambda: [p for p in workers_of(server) if p not in before and p != victim and alive(p)],
        "the parent to start the killed worker again",
        timeout_s=60,
    )
    return int(new[0])


def test_two_workers_share_the_port_state_and_restarts(shared: Cluster, tmp_path: Path) -> None:
    server = shared.start(tmp_path / "node", TWINLINK_WORKERS="2")
    try:
        assert "(2 workers)" in server.log()
        first, second = workers_of(server)
        slug, [device] = device_twin(server)
        send(server, device, 1)

        # Only `second` serves while `first` is dead: it answers, with what `first` stored.
        os.kill(first, signal.SIGKILL)
        send(server, device, 2)
        assert stored(server, slug) == [1, 2]
        third = poll_until(
            lambda: [p for p in workers_of(server) if p != second and alive(p)],
            "the parent to start the killed worker again",
            timeout_s=60,
        )[0]
        assert "worker 1" in server.log() and "starting it again" in server.log()
        # ... and the new one serves alone once `second` is killed in turn.
        kill_and_wait_for_new(server, second)
        send(server, device, 3)
        assert stored(server, slug) == [1, 2, 3]
        assert alive(third) and len(workers_of(server)) == 2
    finally:
        pids = workers_of(server) if server.process.poll() is None else []
        stop_server(server)
    assert server.process.returncode == 0, server.log()
    assert pids and not any(alive(p) for p in pids)  # a stop ends every worker


def test_the_workers_share_the_mqtt_port(shared: Cluster, tmp_path: Path) -> None:
    require_mosquitto()
    server = shared.start(tmp_path / "node", TWINLINK_WORKERS="2")
    try:
        slug, [device] = device_twin(server)
        with server.admin as admin:
            port = int(admin.get("/api/v1/mqtt").json()["address"].rsplit(":", 1)[1])
        workers = workers_of(server)
        for seq, victim in ((1, None), (2, workers[0])):
            if victim is not None:  # the other worker alone listens now
                os.kill(victim, signal.SIGKILL)
                poll_until(lambda v=victim: not alive(v), "the worker to die")
            row = {"time": T0 + seq, "values": {"x": seq}}
            batch = orjson.dumps({"seq": seq, "samples": [row]})
            topic = f"twinlink/{slug}/dev0/telemetry"
            rc, out = asyncio.run(mosquitto_pub(
                port, "-u", "dev0", "-P", device, "-q", "1", "-t", topic, "-m", batch.decode()
            ))  # fmt: skip
            assert rc == 0, f"batch {seq}: {out}\n{server.log()[-3000:]}"
        poll_until(lambda: stored(server, slug) == [1, 2], "both MQTT batches stored")
    finally:
        stop_server(server)


def test_several_workers_without_postgres_and_kafka_are_refused(tmp_path: Path) -> None:
    from tests.conftest import start_server

    with pytest.raises(RuntimeError) as failed:
        start_server(tmp_path / "node", {"TWINLINK_WORKERS": "2"})
    assert "several workers need the shared store and bus" in str(failed.value)
