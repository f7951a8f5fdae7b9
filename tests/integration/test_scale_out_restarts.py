"""Kafka restarted, then PostgreSQL restarted, under a node that devices stream to (issue 15;
docs/decisions/0013-acknowledgement-in-scale-out.md). During the outage the devices get
errors (503 with Retry-After over HTTP, an error with `retry: true` over the WebSocket),
never a 500, a hang or a false ack; afterwards their resends are acknowledged, history holds
every acknowledged sample exactly once, and a live client on the node has seen every
acknowledged batch, those stored during the Kafka outage but published only by their
resend included.

Each test runs a server of its own for the one it restarts (a broker or a PostgreSQL
cluster that other tests share cannot be restarted under them), on the same folder and
ports, so the node finds it where it was.
"""

from __future__ import annotations

import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker, kafka_libs, restart_kafka, start_kafka, stop_kafka
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._postgres import (
    START_S,
    PostgresCluster,
    _ready,
    _start,
    _stop,
    postgres_bin,
)
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._restarts import (
    GOOD,
    SAMPLES,
    UNAVAILABLE,
    HttpDevice,
    LiveClient,
    Streaming,
    WebSocketDevice,
    batch,
    stored,
    unpublished,
)
from tests.integration._scale_out import cluster
from tests.integration._util import poll_until, unhandled_errors

# The session's servers start before the module's first test, which the hygiene check then
# counts (each test's own server is its own, and stopped by it).
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster", "kafka")]

STEADY = 5  # batches each device has acknowledged before and after the outage
OUTAGE_S = 120.0  # how long the devices may take to notice the outage, and to recover
PUBLISH_TIMEOUT_S = "2"  # TWINLINK_BUS_PUBLISH_TIMEOUT_S: the outage shows sooner


@pytest.fixture
def own_kafka(tmp_path: Path) -> Iterator[list[KafkaBroker]]:
    """A broker of this test's own, in a list so the test can put the restarted one back."""
    brokers = [start_kafka(tmp_path / "kafka", kafka_libs())]
    try:
        yield brokers
    finally:
        stop_kafka(brokers[0])


class OwnPostgres:
    """A PostgreSQL cluster of this test's own, stopped and started again on its folder and
    port."""

    def __init__(self) -> None:
        self.bin_dir = postgres_bin()
        self.folder = Path(tempfile.mkdtemp(prefix="twinlink-pg-restart-"))
        self.server, self.port = _start(self.bin_dir, self.folder)
        self.wait_ready()

    @property
    def cluster(self) -> PostgresCluster:
        return PostgresCluster("127.0.0.1", self.port, self.folder)

    def wait_ready(self) -> None:
        deadline = time.monotonic() + START_S
        while not _ready(self.bin_dir, self.port):
            if self.server.poll() is not None or time.monotonic() > deadline:
                log = (self.folder / "postgres.log").read_text(errors="replace")
                pytest.fail(f"PostgreSQL did not start on port {self.port}:\n{log[-3000:]}")
            time.sleep(0.05)  # polling the server's real state, with a deadline

    def stop(self) -> None:
        _stop(self.server)

    def restart(self) -> None:
        self.server, _ = _start(self.bin_dir, self.folder, self.port)
        self.wait_ready()

    def remove(self) -> None:
        _stop(self.server)
        shutil.rmtree(self.folder, ignore_errors=True)


@pytest.fixture
def own_postgres() -> Iterator[OwnPostgres]:
    pg = OwnPostgres()
    try:
        yield pg
    finally:
        pg.remove()


def streaming(node: Server, slug: str, tokens: list[str]) -> list[Streaming]:
    """Two devices over HTTP and one over the device WebSocket, started."""
    http_a, http_b, ws = tokens
    devices = [HttpDevice(node, http_a, 0), HttpDevice(node, http_b, 1)]
    devices.append(WebSocketDevice(node, ws, 2))
    for device in devices:
        device.start()
    return devices


def each_acked(devices: list[Streaming], since: dict[int, int], n: int) -> bool:
    return all(len(d.acked()) - since.get(d.dev, 0) >= n for d in devices)


def until(devices: list[Streaming], node: Server, check: Callable[[], bool], what: str) -> None:
    """Poll `check` with a deadline; when it runs out, say what each device saw."""
    try:
        poll_until(check, what, OUTAGE_S)
    except AssertionError:
        seen = {d.dev: (len(d.acked()), d.outcomes[-3:]) for d in devices}
        raise AssertionError(f"{what}: {seen}\n{node.log()[-3000:]}") from None


def check_outcomes(devices: list[Streaming], node: Server) -> None:
    """Every answer was an ack or an error saying to send again; every batch was sent until
    acknowledged, so the acknowledged seqs are 1..N with none missing, each once."""
    for device in devices:
        wrong = [o for o in device.outcomes if o.kind not in (*GOOD, UNAVAILABLE, "closed")]
        assert not wrong, f"device {device.dev}: {wrong[:5]}\n{node.log()[-3000:]}"
        acked = device.acked()
        assert acked == list(range(1, len(acked) + 1)), (device.dev, acked)
        assert device.count(UNAVAILABLE) >= 1, f"device {device.dev} saw no outage"
    # nothing answered as a bug (500) or a batch failed other than by the outage
    log = node.log()
    assert unhandled_errors(node) == 0 and "storing a batch failed" not in log, log[-5000:]


def check_history(devices: list[Streaming], dsn: str) -> None:
    """History holds every acknowledged sample once, and nothing else."""
    history = stored(dsn)
    for device in devices:
        expected = dict.fromkeys(device.acked(), SAMPLES)
        assert dict(history.get(device.dev, {})) == expected, device.dev


def check_live(devices: list[Streaming], live: LiveClient) -> None:
    """The live client saw every acknowledged batch (a batch the bus took twice may show
    twice: a duplicate on the bus, never a batch missing)."""
    wanted = {(d.dev, seq) for d in devices for seq in d.acked()}
    try:
        poll_until(lambda: wanted <= set(live.seen), "the live client to see every batch", 60)
    except AssertionError:
        missing = sorted(wanted - set(live.seen))
        retried = {(d.dev, o.seq) for d in devices for o in d.outcomes if o.kind != "ack"}
        raise AssertionError(
            f"not seen live: {missing[:20]} ({len(missing)}); sent again: {sorted(retried)[:20]}"
            f"; live errors: {live.errors}"
        ) from None
    assert not live.errors, live.errors


def test_a_kafka_restart_mid_stream_loses_nothing_acknowledged(
    postgres_cluster: PostgresCluster, own_kafka: list[KafkaBroker], tmp_path: Path
) -> None:
    with cluster(postgres_cluster, own_kafka[0]) as shared:
        node = shared.start(tmp_path / "node", TWINLINK_BUS_PUBLISH_TIMEOUT_S=PUBLISH_TIMEOUT_S)
        try:
            slug, tokens = device_twin(node, devices=3)
            live = LiveClient(node, node.admin_token, slug, len(tokens))
            live.start()
            devices = streaming(node, slug, tokens)
            try:
                until(devices, node, lambda: each_acked(devices, {}, STEADY), "steady streaming")
                stop_kafka(own_kafka[0])
                until(devices, node, lambda: all(d.count(UNAVAILABLE) for d in devices), "errors")
                before = {d.dev: len(d.acked()) for d in devices}
                own_kafka[0] = restart_kafka(own_kafka[0])
                until(devices, node, lambda: each_acked(devices, before, STEADY), "recovery")
            finally:
                for device in devices:
                    device.stop()
            check_outcomes(devices, node)
            # The batch each device had in flight when Kafka stopped was stored, not
            # published: its resend was a duplicate, published then (and marked so). The
            # publish that timed out may land too, from the producer's buffer, once Kafka
            # is back: the live client may see such a batch twice, never not at all.
            for device in devices:
                retried = [o for o in device.outcomes if o.kind == "duplicate"]
                assert retried, f"device {device.dev}: no stored-but-unpublished batch"
            poll_until(lambda: unpublished(shared.dsn) == 0, "every batch marked published")
            # the node stopped waiting for Kafka after its bound, not the client's 40 s
            details = [o.detail for d in devices for o in d.outcomes if o.kind == UNAVAILABLE]
            assert any("TWINLINK_BUS_PUBLISH_TIMEOUT_S" in text for text in details), details
            check_history(devices, shared.dsn)
            check_live(devices, live)
            live.stop()
        finally:
            stop_server(node)


def test_a_postgresql_restart_mid_stream_loses_nothing_acknowledged(
    own_postgres: OwnPostgres, kafka: KafkaBroker, tmp_path: Path
) -> None:
    with cluster(own_postgres.cluster, kafka) as shared:
        node = shared.start(tmp_path / "node")
        try:
            slug, tokens = device_twin(node, devices=4)
            unused = tokens.pop()  # a device whose token the node has never checked
            live = LiveClient(node, node.admin_token, slug, len(tokens))
            live.start()
            devices = streaming(node, slug, tokens)
            try:
                until(devices, node, lambda: each_acked(devices, {}, STEADY), "steady streaming")
                own_postgres.stop()
                until(devices, node, lambda: all(d.count(UNAVAILABLE) for d in devices), "errors")
                check_token_during_outage(node, unused)
                before = {d.dev: len(d.acked()) for d in devices}
                own_postgres.restart()
                until(devices, node, lambda: each_acked(devices, before, STEADY), "recovery")
            finally:
                for device in devices:
                    device.stop()
            check_outcomes(devices, node)
            check_history(devices, shared.dsn)
            check_live(devices, live)
            live.stop()
            with node.client(unused) as c:  # the store back: the token is good again
                r = c.post("/api/v1/device/samples", json=batch(3, 1))
                assert r.status_code == 200, r.text
        finally:
            stop_server(node)


def check_token_during_outage(node: Server, token: str) -> None:
    """A device token the node cannot check (the store away) is a 503, not a 401 or a 500."""
    with node.client(token) as c:
        c.timeout = httpx.Timeout(60)
        r = c.post("/api/v1/device/samples", json=batch(3, 1))
    assert r.status_code == 503, r.text
    assert r.headers["retry-after"].isdigit() and "www-authenticate" not in r.headers
