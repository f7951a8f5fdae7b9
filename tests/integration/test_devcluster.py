"""`twinlink cluster up` (make cluster) as a person runs it: a real process starting PostgreSQL,
Kafka, two twinlink nodes and haproxy on free ports, the demo twins loaded through the load
balancer and the simulated rig streaming; then stopped by a signal, leaving nothing running
and its folder kept, from which a second start finds the same admin and twins."""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import httpx
import psutil
import pytest

from tests.conftest import EXAMPLES
from tests.integration._mqtt import require_mosquitto
from tests.integration._util import poll_until

pytestmark = pytest.mark.integration

START_S = 300.0  # initdb, a JVM and two nodes' migrations on a busy 2-core machine
STOP_S = 120.0  # each part's own bound, one after the other
DEMO_TWINS = {"tingen", "ilmatar-k16052", "aalto-industrial-hall"}


@dataclass
class ClusterRun:
    """One `twinlink cluster up` process and what it printed."""

    folder: Path
    process: subprocess.Popen[bytes]
    lines: list[str] = field(default_factory=list)
    reader: threading.Thread | None = None
    url: str = ""
    serving: threading.Event = field(default_factory=threading.Event)

    def output(self) -> str:
        return "".join(self.lines)

    def node_urls(self) -> dict[str, str]:
        found = re.search(r"nodes: (.*)", self.output())
        assert found, self.output()
        return dict(part.split(" ") for part in found.group(1).strip().split(", "))

    def mqtt_port(self) -> int:
        found = re.search(r"MQTT for devices: 127.0.0.1:(\d+)", self.output())
        assert found, self.output()
        return int(found.group(1))

    def admin(self) -> dict[str, str]:
        text = (self.folder / "admin-credentials.txt").read_text()
        return dict(line.split(": ", 1) for line in text.splitlines())

    def descendants(self) -> list[psutil.Process]:
        return psutil.Process(self.process.pid).children(recursive=True)

    def stop(self, sig: signal.Signals) -> int:
        if self.process.poll() is None:
            self.process.send_signal(sig)
        try:
            code = self.process.wait(timeout=STOP_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            raise
        finally:
            if self.reader is not None:
                self.reader.join(timeout=10)
            if self.process.stdout is not None:
                self.process.stdout.close()
        return code


def start_cluster(folder: Path, *options: str) -> ClusterRun:
    """Start `twinlink cluster up` on free ports and wait for its "cluster serving at" line."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("TWINLINK_")}
    command = [sys.executable, "-m", "twinlink", "cluster", "up", "--port", "0", "--mqtt-port",
               "0", "--data-dir", str(folder), "--examples", str(EXAMPLES), *options]  # fmt: skip
    process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    run = ClusterRun(folder, process)

    def pump() -> None:
        assert process.stdout is not None
        for raw in process.stdout:
            line = raw.decode(errors="replace")
            run.lines.append(line)
            if found := re.match(r"cluster serving at (\S+)", line):
                run.url = found.group(1)
                run.serving.set()
        run.serving.set()  # it ended: the waiter sees it did not serve

    run.reader = threading.Thread(target=pump, daemon=True)
    run.reader.start()
    # The command prints the line once everything serves; wait on that, not on a sleep.
    if not run.serving.wait(timeout=START_S) or not run.url:
        run.stop(signal.SIGTERM)
        raise AssertionError(f"the cluster did not start:\n{run.output()}")
    return run


@pytest.fixture(scope="module")
def folder() -> Iterator[Path]:
    # Not pytest's tmp_path: its folders are 0700, and PostgreSQL runs as the user postgres
    # (when the tests run as root), who must enter the cluster's folder.
    path = Path(tempfile.mkdtemp(prefix="twinlink-cluster-"))
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


@pytest.fixture(scope="module")
def cluster(folder: Path) -> Iterator[ClusterRun]:
    run = start_cluster(folder)
    try:
        yield run
    finally:
        run.stop(signal.SIGTERM)


def test_the_demo_twins_are_served_through_the_load_balancer(cluster: ClusterRun) -> None:
    admin = cluster.admin()
    assert (cluster.folder / "admin-credentials.txt").stat().st_mode & 0o777 == 0o600
    # shown once, on the cluster's first start, as make demo shows its first admin
    assert admin["password"] in cluster.output()
    with httpx.Client(base_url=cluster.url, timeout=30) as client:
        login = client.post(
            "/api/v1/auth/login", json={"username": "admin", "password": admin["password"]}
        )
        assert login.status_code == 200, login.text
        session = {"Authorization": f"Bearer {login.json()['token']}"}
        twins = client.get("/api/v1/twins", headers=session)
    assert twins.status_code == 200, twins.text
    assert {t["slug"] for t in twins.json()["items"]} >= DEMO_TWINS


def test_both_nodes_serve_and_share_one_store(cluster: ClusterRun) -> None:
    headers = {"Authorization": f"Bearer {cluster.admin()['token']}"}
    seen: set[str] = set()
    with httpx.Client(base_url=cluster.url, headers=headers, timeout=30) as client:

        def both_answered() -> bool:
            answer = client.get("/api/v1/twins")
            assert answer.status_code == 200, answer.text
            seen.add(answer.headers["x-twinlink-node"])
            return seen == {"node1", "node2"}

        poll_until(both_answered, "an answer from each node through haproxy", timeout_s=60)

    def samples(node_url: str) -> int:
        answer = httpx.get(f"{node_url}/api/v1/twins/tingen/streams", headers=headers, timeout=30)
        assert answer.status_code == 200, answer.text
        streams = {s["name"]: s["samples"] for s in answer.json()["streams"]}
        return int(streams.get("telemetry", 0))

    # The simulated rig streams through haproxy to one node; each node reads the samples
    # from the shared PostgreSQL database.
    nodes = cluster.node_urls()
    assert set(nodes) == {"node1", "node2"}
    for url in nodes.values():
        poll_until(lambda url=url: samples(url) > 0, f"the rig's samples read on {url}", 120)


def test_a_device_publishes_over_mqtt_through_the_load_balancer(cluster: ClusterRun) -> None:
    require_mosquitto()
    headers = {"Authorization": f"Bearer {cluster.admin()['token']}"}
    answer = httpx.post(
        f"{cluster.url}/api/v1/twins/tingen/devices", json={"name": "mqtt-rig"}, headers=headers
    )
    assert answer.status_code == 201, answer.text
    publish = ["mosquitto_pub", "-h", "127.0.0.1", "-p", str(cluster.mqtt_port()), "-q", "1",
               "-t", "twinlink/tingen/mqtt-rig/telemetry", "-m", '{"Input_F_in": 1.5}']  # fmt: skip
    # QoS 1: the PUBACK comes once a node stored the sample, so exit status 0 says it landed
    done = subprocess.run([*publish, "-u", answer.json()["token"]], capture_output=True, timeout=60)
    assert done.returncode == 0, done.stderr
    refused = subprocess.run([*publish, "-u", "tld_wrong"], capture_output=True, timeout=60)
    assert refused.returncode != 0 and b"bad user name or password" in refused.stderr.lower()


def test_a_second_cluster_on_its_port_or_folder_is_refused_before_starting_anything(
    cluster: ClusterRun, tmp_path: Path
) -> None:
    port = cluster.url.rsplit(":", 1)[1]
    up = [sys.executable, "-m", "twinlink", "cluster", "up", "--mqtt-port", "0", "--no-demo"]
    taken = subprocess.run(
        [*up, "--port", port, "--data-dir", str(tmp_path / "other")],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert taken.returncode == 1, taken.stderr
    assert f"127.0.0.1:{port} is taken" in taken.stderr
    assert not (tmp_path / "other" / "postgres").exists()  # nothing was started
    shared = subprocess.run(
        [*up, "--port", "0", "--data-dir", str(cluster.folder)],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert shared.returncode == 1, shared.stderr
    assert f"another twinlink cluster up runs on {cluster.folder}" in shared.stderr
    assert "Traceback" not in taken.stderr + shared.stderr


def test_a_signal_stops_every_part_and_a_second_start_finds_the_same_cluster(
    cluster: ClusterRun,
) -> None:
    parts = cluster.descendants()
    names = {p.name() for p in parts}
    assert {"postgres", "java", "haproxy"} <= names, names
    assert cluster.stop(signal.SIGINT) == 0, cluster.output()
    out = cluster.output()
    for part in ("the simulated rig", "haproxy", "node2", "node1", "Kafka", "PostgreSQL"):
        assert f"{part}: stopping" in out
    # in reverse order of their start
    assert (
        out.index("haproxy: stopping") < out.index("node1: stopping") < out.index("Kafka: stopping")
    )
    assert out.index("Kafka: stopping") < out.index("PostgreSQL: stopping")
    left = [p for p in parts if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
    assert not left, f"still running after the stop: {left}"
    # the folder is kept: data, logs and secrets
    for kept in ("postgres/data/PG_VERSION", "kafka/data/meta.properties", "node1/node.log"):
        assert (cluster.folder / kept).exists(), kept

    again = start_cluster(cluster.folder, "--no-demo")
    try:
        admin = cluster.admin()
        assert admin["password"] not in again.output()  # shown on the first start only
        with httpx.Client(base_url=again.url, timeout=30) as client:
            headers = {"Authorization": f"Bearer {admin['token']}"}
            twins = client.get("/api/v1/twins", headers=headers)
        assert twins.status_code == 200, twins.text
        assert {t["slug"] for t in twins.json()["items"]} >= DEMO_TWINS
        assert "the simulated rig" not in again.output()
    finally:
        assert again.stop(signal.SIGTERM) == 0, again.output()
