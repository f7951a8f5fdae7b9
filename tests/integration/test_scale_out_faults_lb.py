"""Faults of a node behind a load balancer (issue 15): two `twinlink up` nodes on the test
cluster's PostgreSQL and Kafka, behind haproxy checking their /readyz (twinlink.devcluster.haproxy).

- The node a device (the edge SDK, on its WebSocket) streams to is killed with SIGKILL
  mid-stream: the SDK reconnects through haproxy to the other node and resends what had no
  ack; every sample acknowledged is in history once (counted in PostgreSQL and through the
  API), none lost.
- A node cut off from PostgreSQL (a TCP forwarder between them stopped with SIGSTOP) answers
  /readyz 503 without hanging, haproxy takes it out, and a device's batches sent through
  haproxy are all acknowledged by the other node; once the forwarder goes on (SIGCONT) the
  node is ready and back in haproxy.
"""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from urllib.parse import urlsplit

import asyncpg
import httpx
import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import Cluster, cluster
from tests.integration._util import assert_problem, poll_until, unhandled_errors
from tests.integration.test_edge_sdk import BASE_NS, history
from twinlink.devcluster.haproxy import NODE_HEADER, HAProxy, start_haproxy
from twinlink_edge import Ack, Device

pytestmark = pytest.mark.integration

TIMEOUT_S = 60.0  # a deadline for what polls the real state; generous, the machine is shared
# /readyz answers within TWINLINK_READY_TIMEOUT_S (1 s) whatever the store does; a probe
# that takes this long is one that hangs.
PROBE_S = 10.0
SDK_OPTIONS = {"batch_size": 10, "backoff_max": 0.5}
W0 = BASE_NS + 1000  # the WebSocket device's times, after the HTTP device's

# A TCP forwarder from a free loopback port to `host port`: prints its port, then copies
# bytes both ways. Stopped with SIGSTOP, every connection through it goes silent, as a
# database behind a broken network does (nothing closed, nothing answered).
FORWARDER = """
import asyncio, sys

async def pipe(reader, writer):
    try:
        while data := await reader.read(65536):
            writer.write(data)
            await writer.drain()
    except OSError:
        pass
    finally:
        writer.close()

async def main():
    host, port = sys.argv[1], int(sys.argv[2])
    async def handle(reader, writer):
        try:
            up_reader, up_writer = await asyncio.open_connection(host, port)
        except OSError:
            writer.close()
            return
        await asyncio.gather(pipe(reader, up_writer), pipe(up_reader, writer))
    server = await asyncio.start_server(handle, "127.0.0.1", 0)
    print(server.sockets[0].getsockname()[1], flush=True)
    await server.serve_forever()

asyncio.run(main())
"""


@pytest.fixture(scope="module")
def shared(postgres_cluster: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    """One database for the module; each test starts nodes of its own on it."""
    with cluster(postgres_cluster, kafka) as made:
        yield made


def address(server: Server) -> tuple[str, int]:
    parts = urlsplit(server.url)
    assert parts.hostname is not None and parts.port is not None
    return parts.hostname, parts.port


@contextmanager
def balanced(directory: Path, *nodes: Server) -> Iterator[HAProxy]:
    """haproxy in front of `nodes` (node1, node2, ... in this order), once it sees all up."""
    proxy = start_haproxy(directory, 0, [address(node) for node in nodes])
    try:
        names = [f"node{i}" for i in range(1, len(nodes) + 1)]
        poll_until(
            lambda: all(proxy.server_states().get(n) == "UP" for n in names),
            f"haproxy to see {names} up",
            TIMEOUT_S,
        )
        yield proxy
    finally:
        proxy.stop()


@contextmanager
def nodes(shared: Cluster, folder: Path, **env_of_a: str) -> Iterator[tuple[Server, Server]]:
    """Nodes A and B on the shared database and broker; A with `env_of_a` on top."""
    a = shared.start(folder / "node-a", **env_of_a)
    try:
        b = shared.start(folder / "node-b", token=a.admin_token)
        try:
            yield a, b
            for node in (a, b):
                assert unhandled_errors(node) == 0, node.log()[-3000:]
        finally:
            stop_server(b)
    finally:
        stop_server(a)


def connected_to(node: Server, slug: str, device: str = "dev0") -> bool:
    """Whether `node` holds the device's session (each node answers for its own sessions)."""
    with node.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/devices/{device}")
    assert r.status_code == 200, r.text
    return bool(r.json()["connected"])


def stored_times(shared: Cluster, slug: str, signal_name: str = "n") -> dict[int, int]:
    """How many values of a signal PostgreSQL holds at each time of the twin's telemetry."""

    async def read() -> dict[int, int]:
        conn = await asyncpg.connect(shared.dsn)
        try:
            rows = await conn.fetch(
                "SELECT s.t, count(*) AS n FROM samples s"
                " JOIN series se ON se.id = s.series_id"
                " JOIN streams st ON st.id = s.stream_id"
                " JOIN twins tw ON tw.id = st.twin_id"
                " WHERE tw.slug = $1 AND st.name = 'telemetry' AND se.signal = $2"
                " GROUP BY s.t",
                slug,
                signal_name,
            )
        finally:
            await conn.close()
        return {int(row["t"]): int(row["n"]) for row in rows}

    return asyncio.run(read())


# -- kill -9 of the node the device streams to ------------------------------------------------


def test_the_node_a_device_streams_to_killed_mid_stream_loses_nothing(
    shared: Cluster, tmp_path: Path
) -> None:
    with nodes(shared, tmp_path) as (a, b), balanced(tmp_path / "haproxy", a, b) as proxy:
        slug, (token,) = device_twin(a)
        acks = 0
        kill_at: int | None = None
        victim: Server | None = None
        killed = threading.Event()

        def kill_mid_stream(ack: Ack) -> None:  # on the SDK's thread, as acks arrive
            nonlocal acks
            acks += 1
            if victim is not None and acks == kill_at and not killed.is_set():
                os.kill(victim.process.pid, signal.SIGKILL)  # batches are in flight
                killed.set()

        options = {"batch_size": 100, "backoff_max": 0.5, "on_ack": kill_mid_stream}
        with Device(proxy.url, token, **options) as dev:
            for i in range(1000):
                dev.add({"n": i}, time_ns=BASE_NS + i)
            dev.flush(TIMEOUT_S)
            holder = poll_until(
                lambda: next((n for n in (a, b) if connected_to(n, slug)), None),
                "a node holding the device's session",
                TIMEOUT_S,
            )
            survivor = b if holder is a else a
            victim, kill_at = holder, acks + 3
            for i in range(1000, 6000):
                dev.add({"n": i}, time_ns=BASE_NS + i)
            assert killed.wait(TIMEOUT_S)
            holder.process.wait(TIMEOUT_S)
            for i in range(6000, 7000):  # sent on the reconnected session, to the survivor
                dev.add({"n": i}, time_ns=BASE_NS + i)
            dev.flush(TIMEOUT_S)
            stats = dev.stats()
            assert connected_to(survivor, slug)
        dead = "node1" if holder is a else "node2"
        poll_until(lambda: proxy.server_states()[dead].startswith("DOWN"), "dead node out")
        assert stats["acked_samples"] == 7000 and stats["connections"] >= 2, stats
        assert stats["rejected"] == 0 and stats["refused_batches"] == 0, stats
        # Every acknowledged sample once: in the database itself, and through the API.
        counts = stored_times(shared, slug)
        assert sorted(counts) == [BASE_NS + i for i in range(7000)]
        assert set(counts.values()) == {1}
        values = [row["values"]["n"] for row in history(survivor, slug)]
        assert values == list(range(7000))


# -- a node cut off from PostgreSQL ----------------------------------------------------------


@contextmanager
def forwarder(to: tuple[str, int]) -> Iterator[tuple[subprocess.Popen[str], int]]:
    child = subprocess.Popen(
        [sys.executable, "-c", FORWARDER, to[0], str(to[1])],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None
        port = int(child.stdout.readline() or 0)
        assert port, child.stderr.read() if child.stderr else "the forwarder did not start"
        yield child, port
    finally:
        child.send_signal(signal.SIGCONT)  # a stopped process does not act on SIGKILL's exit
        child.kill()
        child.communicate(timeout=TIMEOUT_S)


def readyz(node: Server) -> httpx.Response:
    with httpx.Client(base_url=node.url, timeout=PROBE_S) as c:
        return c.get("/readyz")  # a hang is an httpx.ReadTimeout: the test fails


def send(proxy: HAProxy, token: str, seq: int) -> tuple[str, dict[str, object]]:
    """A batch of one sample through haproxy: which node answered, and its ack."""
    headers = {"Authorization": f"Bearer {token}"}
    rows = [{"time": BASE_NS + seq, "values": {"n": seq}}]
    with httpx.Client(base_url=proxy.url, headers=headers, timeout=PROBE_S) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": rows})
    assert r.status_code == 200, r.text
    return r.headers[NODE_HEADER], r.json()


def test_a_node_cut_off_from_postgres_is_not_ready_and_devices_go_to_the_other(
    shared: Cluster, postgres_cluster: PostgresCluster, tmp_path: Path
) -> None:
    """Batches over HTTP through haproxy (device dev0, signal n), and a WebSocket device
    (the edge SDK, signal w) that was connected to A when A lost its database."""
    database = (postgres_cluster.host, postgres_cluster.port)
    with forwarder(database) as (link, port), ExitStack() as stack:
        store_url = shared.env["TWINLINK_STORE_URL"]
        through = store_url.replace(f":{postgres_cluster.port}/", f":{port}/", 1)
        assert through != store_url
        a, b = stack.enter_context(nodes(shared, tmp_path, TWINLINK_STORE_URL=through))
        proxy = stack.enter_context(balanced(tmp_path / "haproxy", a, b))
        stack.callback(link.send_signal, signal.SIGCONT)  # first thing on the way out
        slug, (token, *sdk_tokens) = device_twin(b, devices=3)
        answered = {send(proxy, token, seq)[0] for seq in range(1, 5)}
        assert answered == {"node1", "node2"}  # both nodes take batches while ready
        # Two SDK devices connected one after the other: haproxy puts one on each node.
        sdk = []
        for sdk_token in sdk_tokens:
            sdk.append(stack.enter_context(Device(proxy.url, sdk_token, **SDK_OPTIONS)))
            assert sdk[-1].wait_connected(TIMEOUT_S)
        on_a = poll_until(
            lambda: [i for i in (1, 2) if connected_to(a, slug, f"dev{i}")], "a device on A"
        )
        name, stuck = f"dev{on_a[0]}", sdk[on_a[0] - 1]
        for i in range(10):
            stuck.add({"w": i}, time_ns=W0 + i)
        stuck.flush(TIMEOUT_S)

        link.send_signal(signal.SIGSTOP)  # node A's database goes silent
        for i in range(10, 50):  # to A, which cannot store them
            stuck.add({"w": i}, time_ns=W0 + i)
        body = assert_problem(readyz(a), 503)
        assert body["detail"] == "the store does not answer within 1 s"
        assert readyz(b).status_code == 200
        poll_until(lambda: proxy.server_states()["node1"].startswith("DOWN"), "haproxy: A down")
        for seq in range(5, 25):
            node, ack = send(proxy, token, seq)
            assert node == "node2", f"batch {seq} went to {node}"
            assert ack["accepted"] == 1 and ack["duplicate"] is False, ack
        # haproxy closed the device's connection to A: it reconnects to B and resends there.
        stuck.flush(TIMEOUT_S)
        assert connected_to(b, slug, name) and stuck.stats()["connections"] >= 2

        link.send_signal(signal.SIGCONT)  # and answers again
        poll_until(lambda: readyz(a).status_code == 200, "A ready again", TIMEOUT_S)
        poll_until(lambda: proxy.server_states()["node1"] == "UP", "haproxy: A up again")
        answered = {send(proxy, token, seq)[0] for seq in range(25, 29)}
        assert answered == {"node1", "node2"}
        # Each batch once, the WebSocket device's that A had taken but not stored included.
        assert stored_times(shared, slug, "w") == {W0 + i: 1 for i in range(50)}
        assert stored_times(shared, slug, "n") == {BASE_NS + i: 1 for i in range(1, 29)}
        rows = history(b, slug)
        assert [r["values"]["n"] for r in rows if "n" in r["values"]] == list(range(1, 29))
