"""`twinlink cluster up`: PostgreSQL, a Kafka broker, N twinlink nodes and haproxy in front of
them, on this machine's loopback, with the demo twins (docs/scale-out.md, "A local cluster").

Everything lives in one folder (./.twinlink-cluster by default), kept across starts:

    secret-key, database-password, admin-credentials.txt   the secrets (mode 0600)
    postgres/   the database cluster (owned by the `postgres` user when run as root), its log
    kafka/      the broker's config, data and broker.log
    node1/ ...  each node's data dir and node.log
    haproxy/    haproxy.cfg, haproxy.log, its stats socket
    simulator.log   the demo's simulated rig

Started in the order each part needs the one before it; stopped in the reverse order, each
part given a bound and then killed: the rig (its last batches acknowledged), haproxy, the
nodes (leases and sessions handed over), Kafka, PostgreSQL.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import signal
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import httpx

from twinlink.devcluster import demo
from twinlink.devcluster._process import free_ports, port_free
from twinlink.devcluster.credentials import (
    ADMIN,
    ClusterSecrets,
    CredentialsError,
    load_or_create,
)
from twinlink.devcluster.demo import DemoError
from twinlink.devcluster.haproxy import HAProxy, HAProxyError, start_haproxy
from twinlink.devcluster.kafka import KafkaBroker, KafkaError, kafka_libs, start_kafka
from twinlink.devcluster.nodes import Node, NodeError, launch_node, wait_serving
from twinlink.devcluster.postgres import PostgresError, PostgresServer, start_postgres
from twinlink.domain.errors import TwinlinkError

DATABASE = ROLE = "twinlink"
BALANCED_S = 60.0  # haproxy sees a new node up after two good checks, 500 ms apart
Say = Callable[[str], None]


class ClusterError(TwinlinkError):
    """A part of the cluster did not start; the message says which and where its log is."""


@dataclass(frozen=True)
class ClusterOptions:
    data_dir: Path = Path(".twinlink-cluster")
    port: int = 8000  # the load balancer's, on 127.0.0.1; 0 for any free one
    mqtt_port: int = 1883  # its MQTT front end's; any free one when 0 or taken
    nodes: int = 2
    demo: bool = True
    examples: Path = Path("examples")  # the demo's DT documents
    health_path: str = "/readyz"


class LocalCluster:
    def __init__(self, options: ClusterOptions, say: Say) -> None:
        self.options = options
        self.folder = options.data_dir.absolute()
        self.say = say
        self.secrets: ClusterSecrets | None = None
        self.postgres: PostgresServer | None = None
        self.kafka: KafkaBroker | None = None
        self.haproxy: HAProxy | None = None
        self.nodes: list[Node] = []
        self.simulator: demo.Simulator | None = None
        self.twins: list[str] = []
        self._lock: IO[str] | None = None  # held while this command runs the folder's cluster

    @property
    def url(self) -> str:
        assert self.haproxy is not None, "the cluster has not started"
        return self.haproxy.url

    def start(self) -> None:
        """Start every part, in order; ClusterError when one does not start (what did start
        is left for `stop`)."""
        self._prepare_folder()
        self._check_free()
        self.secrets = load_or_create(self.folder)
        self.say(f"PostgreSQL: starting ({self.folder / 'postgres'})")
        self.postgres = self._start_postgres()
        self.say("Kafka: starting (the jars in .cache/kafka, fetched the first time)")
        self.kafka = start_kafka(self.folder / "kafka", kafka_libs())
        self._start_nodes_behind_haproxy()
        if self.options.demo:
            self._start_demo()

    def _check_free(self) -> None:
        """Before anything starts: the folder is this command's alone (a second command on it
        would start a second PostgreSQL on the same data), and the load balancer's port is
        free (`make demo` or another cluster may hold it)."""
        self._lock = (self.folder / "cluster.lock").open("w")
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise ClusterError(
                f"another twinlink cluster up runs on {self.folder}: stop it first, or give "
                "this one another --data-dir"
            ) from None
        port = self.options.port
        if port and not port_free(port):
            raise ClusterError(
                f"127.0.0.1:{port} is taken (make demo, or another cluster?): stop what holds "
                "it, or give another --port (make cluster PORT=...), 0 for any free one"
            )

    def _prepare_folder(self) -> None:
        # Others may enter it but not list it: PostgreSQL's own folder inside must be
        # reachable by the `postgres` user when run as root; the secrets are 0600.
        self.folder.mkdir(mode=0o711, parents=True, exist_ok=True)
        if os.geteuid() == 0:
            self.folder.chmod(0o711)
        nodes = [f"node{i + 1}" for i in range(self.options.nodes)]
        for name in ("kafka", "haproxy", *nodes):
            (self.folder / name).mkdir(mode=0o700, exist_ok=True)

    def _start_postgres(self) -> PostgresServer:
        assert self.secrets is not None
        try:
            server = start_postgres(self.folder / "postgres")
        except PostgresError as err:
            hint = ""
            if os.geteuid() == 0:
                hint = (
                    f"\n(run as root, PostgreSQL runs as the user postgres, who must be able "
                    f"to enter every folder above {self.folder})"
                )
            raise ClusterError(f"{err}{hint}") from err
        _ensure_database(server, self.secrets.database_password)
        return server

    def _node_env(self, public_url: str) -> dict[str, str]:
        assert self.secrets is not None and self.postgres is not None and self.kafka is not None
        return {
            "TWINLINK_STORE_URL": (
                f"postgresql://{ROLE}:{self.secrets.database_password}"
                f"@127.0.0.1:{self.postgres.port}/{DATABASE}"
            ),
            "TWINLINK_BUS_URL": f"kafka://{self.kafka.bootstrap}",
            "TWINLINK_SECRET_KEY": self.secrets.secret_key,
            "TWINLINK_PUBLIC_URL": public_url,
            "TWINLINK_ADMIN_TOKEN": self.secrets.admin_token,
            "TWINLINK_ADMIN_PASSWORD": self.secrets.admin_password,
        }

    def _start_nodes_behind_haproxy(self) -> None:
        """haproxy first (its port, perhaps a free one, is the nodes' public URL), then the
        first node alone (it creates the schema and the admin on a new database), then the
        others side by side; returns once haproxy has seen every node up."""
        count = self.options.nodes
        ports = free_ports(2 * count)  # HTTP and MQTT of each node
        backends = [("127.0.0.1", port) for port in ports[:count]]
        mqtt_port = self.options.mqtt_port
        if mqtt_port and not port_free(mqtt_port):
            self.say(f"MQTT: 127.0.0.1:{mqtt_port} is taken, the cluster takes any free port")
            mqtt_port = 0
        self.say(f"haproxy: starting on 127.0.0.1:{self.options.port or '(any free port)'}")
        self.haproxy = start_haproxy(
            self.folder / "haproxy", self.options.port, backends, self.options.health_path,
            mqtt_backends=[("127.0.0.1", port) for port in ports[count:]], mqtt_port=mqtt_port,
        )  # fmt: skip
        env = self._node_env(self.haproxy.url)
        for i in range(count):
            name = f"node{i + 1}"
            self.say(f"{name}: starting on 127.0.0.1:{ports[i]} (MQTT {ports[count + i]})")
            mqtt = {"TWINLINK_MQTT_PORT": str(ports[count + i])}
            self.nodes.append(launch_node(name, self.folder / name, ports[i], {**env, **mqtt}))
            if i == 0:
                wait_serving(self.nodes[0])
        for node in self.nodes[1:]:
            wait_serving(node)
        self._wait_balanced()

    def _wait_balanced(self) -> None:
        assert self.haproxy is not None
        deadline = time.monotonic() + BALANCED_S
        while True:
            states = self.haproxy.server_states() | {
                f"{name} (MQTT)": state
                for name, state in self.haproxy.server_states("mqtt").items()
            }
            if all(state == "UP" for state in states.values()):
                return
            if time.monotonic() > deadline:
                raise ClusterError(
                    f"haproxy did not see every node up on {self.options.health_path} within "
                    f"{BALANCED_S:.0f} s: {states} (log: {self.haproxy.directory})"
                )
            time.sleep(0.2)  # polling haproxy's real view, with a deadline

    def _start_demo(self) -> None:
        assert self.secrets is not None
        headers = {"Authorization": f"Bearer {self.secrets.admin_token}"}
        with httpx.Client(base_url=self.url, headers=headers, timeout=60) as client:
            self.twins = demo.load_examples(client, self.options.examples)
            token = demo.device_token(client)
        if token is not None:
            self.simulator = demo.start_simulator(self.url, token, self.folder / "simulator.log")

    def welcome(self) -> str:
        """What a person needs to use the cluster (no secret but on its first start)."""
        assert self.secrets is not None
        lines = [f"cluster serving at {self.url}"]
        if self.secrets.created:
            lines += [
                "  the cluster created its admin; this is shown once, keep it safe:",
                f"    username: {ADMIN}",
                f"    password: {self.secrets.admin_password}",
                f"    API token: {self.secrets.admin_token}",
            ]
        lines += [
            f"  nodes: {', '.join(f'{n.name} {n.url}' for n in self.nodes)}",
            f"  MQTT for devices: 127.0.0.1:{self.haproxy.mqtt_port if self.haproxy else '?'} "
            "(any node; topics twinlink/{twin}/{device}/..., docs/mqtt.md)",
            f"  PostgreSQL 127.0.0.1:{self.postgres.port if self.postgres else '?'}, "
            f"Kafka {self.kafka.bootstrap if self.kafka else '?'}",
            f"  demo twins: {', '.join(self.twins) or 'none (--no-demo)'}",
            f"  open {self.url}/app/ (the web app; Tingen live at /app/twins/tingen/live), "
            f"{self.url}/docs (API)",
            f"  sign in as {ADMIN}; the password and token are in "
            f"{self.folder / 'admin-credentials.txt'}",
            f"  CLI: twinlink --url {self.url} login -u {ADMIN}",
            f"  logs and data in {self.folder}; Ctrl-C stops the cluster (twice: kills it)",
        ]
        return "\n".join(lines)

    def parts(self) -> list[Part]:
        """Every running part of the cluster, in the order they stop."""
        parts: list[Part] = []
        if self.simulator is not None:
            parts.append(Part("the simulated rig", self.simulator.process, self.simulator.stop))
        if self.haproxy is not None:
            parts.append(Part("haproxy", self.haproxy.process, self.haproxy.stop))
        parts += [Part(node.name, node.process, node.stop) for node in reversed(self.nodes)]
        if self.kafka is not None:
            parts.append(Part("Kafka", self.kafka.process, self.kafka.stop))
        if self.postgres is not None:
            parts.append(Part("PostgreSQL", self.postgres.process, self.postgres.stop))
        return parts

    def stop(self) -> None:
        """Stop each part in the reverse order of their start, each with its own bound."""
        for part in self.parts():
            if part.process.poll() is None:
                self.say(f"{part.name}: stopping")
            part.stop()
        if self._lock is not None:
            self._lock.close()  # the folder is free for the next start

    def kill(self) -> None:
        """Kill every process at once (a second Ctrl-C). PostgreSQL gets its immediate
        shutdown (SIGQUIT), which ends its backends too; its data recovers on the next start."""
        for part in self.parts():
            if part.process.poll() is None:
                with contextlib.suppress(ProcessLookupError):
                    part.process.send_signal(
                        signal.SIGQUIT if part.name == "PostgreSQL" else signal.SIGKILL
                    )
        for part in self.parts():
            part.process.wait()


@dataclass(frozen=True)
class Part:
    name: str
    process: subprocess.Popen[bytes]
    stop: Callable[[], None]


# What a part that did not start raises: each says which part and where its log is.
START_ERRORS = (
    ClusterError, CredentialsError, DemoError, HAProxyError, KafkaError, NodeError,
    PostgresError,
    httpx.HTTPError,  # the demo's calls through the load balancer
    OSError,  # a folder or file of the cluster's that cannot be made or read
)  # fmt: skip


def run(options: ClusterOptions, say: Say) -> None:
    """Start the cluster, say its welcome, and keep it until SIGINT or SIGTERM; then stop it
    (a second signal while it stops kills it). ClusterError, after stopping what had
    started, when a part did not start."""
    cluster = LocalCluster(options, say)
    # Both set here, SIGINT too: a shell starts a background job with SIGINT ignored, which
    # Python then leaves ignored (and the parts started would inherit)
    previous = {sig: signal.signal(sig, _interrupt) for sig in (signal.SIGINT, signal.SIGTERM)}
    failure: Exception | None = None
    try:
        cluster.start()
        say(cluster.welcome())
        _watch(cluster, say)
    except KeyboardInterrupt:
        say("stopping the cluster")
    except START_ERRORS as err:
        failure = err
        say("the cluster did not start; stopping what had started")
    finally:
        try:
            cluster.stop()
        except KeyboardInterrupt:
            say("killing the cluster")
            cluster.kill()
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    if failure is not None:
        raise ClusterError(str(failure)) from failure


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt  # SIGTERM stops the cluster as Ctrl-C does; a second one kills


def _watch(cluster: LocalCluster, say: Say) -> None:
    """Until interrupted: say once about each part that ended on its own (its log says why;
    the rest keeps running, as a cluster that lost a node does)."""
    told: set[str] = set()
    while True:
        for part in cluster.parts():
            code = part.process.poll()
            if code is not None and part.name not in told:
                told.add(part.name)
                say(f"{part.name} exited with {code} (its log is in {cluster.folder})")
        time.sleep(1.0)  # a person reads these; no hurry


def _ensure_database(server: PostgresServer, password: str) -> None:
    """The role `twinlink` (its password the one kept in the folder) and its database."""
    has_role = server.psql(f"SELECT 1 FROM pg_roles WHERE rolname = '{ROLE}'").strip()
    verb = "ALTER" if has_role else "CREATE"
    try:
        server.psql(f"{verb} ROLE {ROLE} LOGIN PASSWORD '{password}'")
    except PostgresError:
        # psql's message would quote the statement, password and all
        raise ClusterError(f"PostgreSQL refused to {verb.lower()} the role {ROLE}") from None
    if not server.psql(f"SELECT 1 FROM pg_database WHERE datname = '{DATABASE}'").strip():
        server.psql(f"CREATE DATABASE {DATABASE} OWNER {ROLE}")
