"""An Apache Kafka broker: one KRaft node (broker and controller in one JVM, no ZooKeeper),
run from the Maven Central jars that scripts/ensure-kafka.sh keeps in
.cache/kafka/<version>/libs, on loopback ports, for the local cluster and the tests.

The folder given keeps the broker's config, its data (formatted once, so a restart on the
same folder and ports keeps the topics and their messages) and its log.
"""

from __future__ import annotations

import contextlib
import secrets
import signal
import socket
import struct
import subprocess
import time
from base64 import urlsafe_b64encode
from dataclasses import dataclass
from pathlib import Path

from twinlink.devcluster._process import dying_with_parent, free_ports, stop_process
from twinlink.domain.errors import TwinlinkError

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
# src/twinlink/devcluster/kafka.py -> the checkout, whose scripts/ fetch the jars
CHECKOUT = Path(__file__).resolve().parents[3]


class KafkaError(TwinlinkError):
    """The broker's jars could not be had, or the broker did not start."""


class _PortTaken(KafkaError):
    pass


@dataclass
class KafkaBroker:
    bootstrap: str  # host:port of the PLAINTEXT listener, for clients
    directory: Path  # its config, data and log
    process: subprocess.Popen[bytes]
    libs: Path | None = None  # the jars it runs from (restart_kafka runs the same)
    controller_port: int = 0

    @property
    def port(self) -> int:
        return int(self.bootstrap.rsplit(":", 1)[1])

    def log(self, tail: int = 4000) -> str:
        with contextlib.suppress(OSError):
            return (self.directory / "broker.log").read_text(errors="replace")[-tail:]
        return ""

    def stop(self) -> None:
        stop_kafka(self)


def kafka_libs(checkout: Path = CHECKOUT) -> Path:
    """The folder of the broker's jars, fetched first if need be (Java 17 and Maven)."""
    script = checkout / "scripts" / "ensure-kafka.sh"
    if not script.exists():
        raise KafkaError(
            f"{script} not found: the local cluster's Kafka runs from a twinlink checkout "
            "(git clone, then make cluster)"
        )
    done = subprocess.run(["bash", str(script)], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise KafkaError(f"scripts/ensure-kafka.sh failed:\n{done.stderr}")
    return Path(done.stdout.strip().splitlines()[-1])


def start_kafka(
    directory: Path, libs: Path, port: int = 0, controller_port: int = 0
) -> KafkaBroker:
    """Format the KRaft data folder (once) and start the broker on 127.0.0.1:`port` (0: free
    ports, tried again on others when one was taken before the JVM bound it: other servers
    pick free ports at the same time); returns once it answers requests."""
    directory.mkdir(parents=True, exist_ok=True)
    for _attempt in range(3):
        ports = free_ports(2)
        try:
            return _start_once(directory, libs, port or ports[0], controller_port or ports[1])
        except _PortTaken:
            if port and controller_port:
                raise
    raise KafkaError("the Kafka broker found its ports taken three times in a row")


def restart_kafka(broker: KafkaBroker) -> KafkaBroker:
    """Stop the broker if it runs and start it again on the same folder, data and ports."""
    if broker.libs is None:
        raise ValueError("restart_kafka needs a broker started by start_kafka")
    stop_kafka(broker)
    return start_kafka(broker.directory, broker.libs, broker.port, broker.controller_port)


def _start_once(directory: Path, libs: Path, port: int, controller_port: int) -> KafkaBroker:
    config = directory / "server.properties"
    config.write_text(_server_properties(directory / "data", port, controller_port))
    (directory / "log4j2.properties").write_text(LOG4J2)
    java = ["java", *JVM_OPTIONS, f"-Dlog4j2.configurationFile={directory / 'log4j2.properties'}"]
    classpath = ["-cp", f"{libs}/*"]
    if not (directory / "data" / "meta.properties").exists():
        _format(java, classpath, config)
    with (directory / "broker.log").open("wb") as log:
        process = subprocess.Popen(
            [*java, *classpath, "kafka.Kafka", str(config)],
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            preexec_fn=dying_with_parent(signal.SIGKILL),
            process_group=0,  # a Ctrl-C in the terminal reaches the launcher alone
        )
    broker = KafkaBroker(f"127.0.0.1:{port}", directory, process, libs, controller_port)
    try:
        _wait_until_answering(broker)
    except BaseException as err:
        stop_kafka(broker)
        if "Address already in use" in broker.log(tail=100_000):
            raise _PortTaken(f"port {port} or {controller_port} taken") from err
        raise
    return broker


def _format(java: list[str], classpath: list[str], config: Path) -> None:
    cluster_id = urlsafe_b64encode(secrets.token_bytes(16)).decode().rstrip("=")
    storage_tool = [*classpath, "kafka.tools.StorageTool"]  # what kafka-storage.sh runs
    formatted = subprocess.run(
        [*java, *storage_tool, "format", "-t", cluster_id, "-c", str(config)],
        capture_output=True,
        text=True,
        check=False,
    )
    if formatted.returncode != 0:
        raise KafkaError(f"kafka-storage format failed:\n{formatted.stdout}{formatted.stderr}")


def stop_kafka(broker: KafkaBroker) -> None:
    """SIGTERM (the broker shuts down cleanly), then SIGKILL if it takes too long."""
    stop_process(broker.process, signal.SIGTERM, STOP_S)


def _wait_until_answering(broker: KafkaBroker) -> None:
    """Poll with an ApiVersions request until the broker answers it without an error: the
    listener takes connections only once the broker has started, but ask to be sure."""
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        if broker.process.poll() is not None:
            code = broker.process.returncode
            raise KafkaError(f"the Kafka broker exited with {code}:\n{broker.log()}")
        if _answers_api_versions("127.0.0.1", broker.port):
            return
        time.sleep(0.1)  # polling the broker's real state, with a deadline
    raise KafkaError(f"the Kafka broker did not answer within {START_S:.0f} s:\n{broker.log()}")


def _answers_api_versions(host: str, port: int) -> bool:
    client_id = b"twinlink-devcluster"
    # ApiVersions v0: api key 18, version 0, correlation id, client id (int16 length + bytes).
    body = struct.pack(">hhih", 18, 0, 1, len(client_id)) + client_id
    try:
        with socket.create_connection((host, port), timeout=2) as conn:
            conn.sendall(struct.pack(">i", len(body)) + body)
            header = _read_exactly(conn, 10)  # size, correlation id, error code
    except OSError:
        return False
    _size, correlation, error = struct.unpack(">iih", header)
    return bool(correlation == 1 and error == 0)


def _read_exactly(conn: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            raise ConnectionError("closed")
        data += chunk
    return data


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
