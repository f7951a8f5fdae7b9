"""A real Apache Kafka broker for the tests: one KRaft node (broker and controller in one JVM,
no ZooKeeper), run from the Maven Central jars that scripts/ensure-kafka.sh keeps in
.cache/kafka/<version>/libs, on free loopback ports in a temporary folder.

One broker serves the whole session, started by the first test that asks for the `kafka`
fixture. A test module imports the fixture (`from tests.integration._kafka import kafka`);
pytest then holds one fixture per module, so the broker itself is kept here, started once
and stopped when the session's last such fixture ends. Being session-scoped, the fixture is
set up before a module's own fixtures, so the leak check (tests/_hygiene.py) does not count
the JVM against the module or the test that first asked for it.
"""

from __future__ import annotations

import contextlib
import ctypes
import secrets
import signal
import socket
import struct
import subprocess
import time
from base64 import urlsafe_b64encode
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.conftest import ROOT

START_S = 60.0  # a JVM on a busy 2-core machine; it is ready in about 3 s when idle
STOP_S = 20.0
JVM_OPTIONS = [
    "-Xmx512m",
    "-Xms64m",
    "-XX:+UseSerialGC",  # one small heap: no parallel collector threads on a 2-core machine
    "-XX:TieredStopAtLevel=1",  # C1 only: starts sooner, fast enough for tests
    "-XX:-UsePerfData",  # no hsperfdata files in /tmp
    "-Djava.awt.headless=true",
]
_PR_SET_PDEATHSIG = 1


@dataclass
class KafkaBroker:
    bootstrap: str  # host:port of the PLAINTEXT listener, for clients
    directory: Path  # its config, data and log
    process: subprocess.Popen[bytes]

    def log(self, tail: int = 4000) -> str:
        with contextlib.suppress(OSError):
            return (self.directory / "broker.log").read_text(errors="replace")[-tail:]
        return ""


def kafka_libs() -> Path:
    """The folder of the broker's jars, fetched first if need be."""
    done = subprocess.run(
        ["bash", str(ROOT / "scripts" / "ensure-kafka.sh")],
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        pytest.fail(f"scripts/ensure-kafka.sh failed:\n{done.stderr}", pytrace=False)
    return Path(done.stdout.strip().splitlines()[-1])


def start_kafka(directory: Path, libs: Path) -> KafkaBroker:
    """Format a KRaft log folder and start the broker; returns once it answers requests.
    Tries again on other ports when one it was given was taken before the JVM bound it (the
    other engineers' servers pick free ports at the same time)."""
    for attempt in range(1, 4):
        try:
            return _start_once(directory / f"attempt-{attempt}", libs)
        except _PortTaken:
            continue
    raise RuntimeError("the Kafka broker found its ports taken three times in a row")


class _PortTaken(RuntimeError):
    pass


def _start_once(directory: Path, libs: Path) -> KafkaBroker:
    directory.mkdir()
    port, controller_port = _free_ports(2)
    config = directory / "server.properties"
    config.write_text(_server_properties(directory / "data", port, controller_port))
    (directory / "log4j2.properties").write_text(LOG4J2)
    java = ["java", *JVM_OPTIONS, f"-Dlog4j2.configurationFile={directory / 'log4j2.properties'}"]
    classpath = ["-cp", f"{libs}/*"]
    cluster_id = urlsafe_b64encode(secrets.token_bytes(16)).decode().rstrip("=")
    storage_tool = [*classpath, "kafka.tools.StorageTool"]  # what kafka-storage.sh runs
    formatted = subprocess.run(
        [*java, *storage_tool, "format", "-t", cluster_id, "-c", str(config)],
        capture_output=True,
        text=True,
        check=False,
    )
    if formatted.returncode != 0:
        raise RuntimeError(f"kafka-storage format failed:\n{formatted.stdout}{formatted.stderr}")
    with (directory / "broker.log").open("wb") as log:
        process = subprocess.Popen(
            [*java, *classpath, "kafka.Kafka", str(config)],
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            # the fixture runs in pytest's main thread, whose exit is what the kernel watches
            preexec_fn=_die_with_parent,
        )
    broker = KafkaBroker(f"127.0.0.1:{port}", directory, process)
    try:
        _wait_until_answering(broker)
    except BaseException as err:
        stop_kafka(broker)
        if "Address already in use" in broker.log(tail=100_000):
            raise _PortTaken() from err
        raise
    return broker


def _free_ports(n: int) -> list[int]:
    """n different free ports (free_port twice may well give the same one twice)."""
    with contextlib.ExitStack() as held:
        sockets = [held.enter_context(socket.socket()) for _ in range(n)]
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [int(s.getsockname()[1]) for s in sockets]


def stop_kafka(broker: KafkaBroker) -> None:
    """SIGTERM (the broker shuts down cleanly), then SIGKILL if it takes too long."""
    if broker.process.poll() is None:
        broker.process.send_signal(signal.SIGTERM)
        try:
            broker.process.wait(timeout=STOP_S)
        except subprocess.TimeoutExpired:
            broker.process.kill()
            broker.process.wait()


def _wait_until_answering(broker: KafkaBroker) -> None:
    """Poll with an ApiVersions request until the broker answers it without an error: the
    listener takes connections only once the broker has started, but ask to be sure."""
    host, port = broker.bootstrap.rsplit(":", 1)
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        if broker.process.poll() is not None:
            code = broker.process.returncode
            raise RuntimeError(f"the Kafka broker exited with {code}:\n{broker.log()}")
        if _answers_api_versions(host, int(port)):
            return
        time.sleep(0.1)
    raise RuntimeError(f"the Kafka broker did not answer within {START_S:.0f} s:\n{broker.log()}")


def _answers_api_versions(host: str, port: int) -> bool:
    client_id = b"twinlink-tests"
    # ApiVersions v0: api key 18, version 0, correlation id, client id (int16 length + bytes).
    body = struct.pack(">hhih", 18, 0, 1, len(client_id)) + client_id
    try:
        with socket.create_connection((host, port), timeout=2) as conn:
            conn.sendall(struct.pack(">i", len(body)) + body)
            header = _read_exactly(conn, 10)  # size, correlation id, error code
    except OSError:
        return False
    _size, correlation, error = struct.unpack(">iih", header)
    return correlation == 1 and error == 0


def _read_exactly(conn: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            raise ConnectionError("closed")
        data += chunk
    return data


def _die_with_parent() -> None:
    """In the child before exec: the kernel kills the JVM when pytest dies, even by SIGKILL,
    so an interrupted run leaves no broker behind."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)


def _server_properties(data: Path, port: int, controller_port: int) -> str:
    return f"""\
process.roles=broker,controller
node.id=1
controller.quorum.voters=1@127.0.0.1:{controller_port}
listeners=PLAINTEXT://127.0.0.1:{port},CONTROLLER://127.0.0.1:{controller_port}
advertised.listeners=PLAINTEXT://127.0.0.1:{port}
controller.listener.names=CONTROLLER
inter.broker.listener.name=PLAINTEXT
listener.security.protocol.map=CONTROLLER:PLAINTEXT,PLAINTEXT:PLAINTEXT
log.dirs={data}
num.partitions=4
offsets.topic.replication.factor=1
offsets.topic.num.partitions=4
transaction.state.log.replication.factor=1
transaction.state.log.min.isr=1
share.coordinator.state.topic.replication.factor=1
share.coordinator.state.topic.min.isr=1
group.initial.rebalance.delay.ms=0
num.network.threads=2
num.io.threads=2
num.recovery.threads.per.data.dir=1
"""


# Warnings and errors only, to broker.log (the JVM's stdout): INFO is a few hundred lines a start.
LOG4J2 = """\
status = warn
appender.out.type = Console
appender.out.name = out
appender.out.layout.type = PatternLayout
appender.out.layout.pattern = %d{HH:mm:ss.SSS} %p %c{1}: %m%n
rootLogger.level = warn
rootLogger.appenderRef.out.ref = out
"""

_broker: KafkaBroker | None = None
_users = 0


@pytest.fixture(scope="session")
def kafka(tmp_path_factory: pytest.TempPathFactory) -> Iterator[KafkaBroker]:
    """The session's Kafka broker (started by the first module that asks)."""
    global _broker, _users
    if _broker is None or _broker.process.poll() is not None:
        _broker = start_kafka(tmp_path_factory.mktemp("kafka"), kafka_libs())
    _users += 1
    try:
        yield _broker
    finally:
        _users -= 1
        if _users == 0:
            stop_kafka(_broker)
            _broker = None
