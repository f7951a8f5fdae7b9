"""What the cluster benchmark runs against: the embedded server, or `twinlink up` nodes on a
PostgreSQL database and a Kafka broker, behind haproxy when there are several.

PostgreSQL, Kafka and haproxy come from `twinlink.devcluster` (the launchers `make cluster`
uses). PostgreSQL runs as a kept cluster would (fsync on, synchronous commit, full-page
writes: an ack survives a power cut, as the embedded store's `history_sync` full), not as the
tests' throwaway one. One server and one broker serve every case of a run; each case gets a
database of its own and nodes started for it.
"""

from __future__ import annotations

import contextlib
import re
import secrets
import shutil
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import httpx
from cryptography.fernet import Fernet

from _server import Twinlink
from twinlink.devcluster.haproxy import HAProxy, start_haproxy
from twinlink.devcluster.kafka import KafkaBroker, kafka_libs, start_kafka
from twinlink.devcluster.postgres import PostgresServer, start_postgres

ROLE = "bench"


@dataclass
class Infra:
    """PostgreSQL and Kafka for the whole run, in a temporary folder removed by `stop`."""

    folder: Path
    postgres: PostgresServer | None = None
    kafka: KafkaBroker | None = None
    password: str = field(default_factory=lambda: secrets.token_urlsafe(16))
    secret_key: str = field(default_factory=lambda: Fernet.generate_key().decode())
    databases: int = 0

    @classmethod
    def start(cls) -> Infra:
        infra = cls(Path(tempfile.mkdtemp(prefix="twinlink-bench-cluster-")))
        infra.folder.chmod(0o755)  # run as root, the server runs as `postgres`: let it in
        try:
            infra.postgres = start_postgres(infra.folder / "postgres", throwaway=False)
            # a kept cluster asks for a password over TCP, as a real deployment does
            infra.postgres.psql(f"CREATE ROLE {ROLE} LOGIN PASSWORD '{infra.password}'")
            infra.kafka = start_kafka(infra.folder / "kafka", kafka_libs())
        except BaseException:
            infra.stop()
            raise
        return infra

    def new_database(self) -> str:
        """A fresh database for one case; the store URL the nodes get."""
        assert self.postgres is not None
        self.databases += 1
        name = f"bench{self.databases}"
        self.postgres.psql(f'CREATE DATABASE "{name}" OWNER {ROLE}')
        return f"postgresql://{ROLE}:{self.password}@127.0.0.1:{self.postgres.port}/{name}"

    def pids(self) -> dict[str, int]:
        found = {}
        if self.postgres is not None:
            found["postgres"] = self.postgres.process.pid
        if self.kafka is not None:
            found["kafka"] = self.kafka.process.pid
        return found

    def stop(self) -> None:
        for part in (self.kafka, self.postgres):
            if part is not None:
                with contextlib.suppress(Exception):
                    part.stop()
        shutil.rmtree(self.folder, ignore_errors=True)


@dataclass
class Setup:
    """One case's servers: `entry` is where devices post (haproxy's URL in the cluster)."""

    name: str
    nodes: list[Twinlink]
    folder: Path
    infra: Infra | None = None
    haproxy: HAProxy | None = None

    @property
    def entry(self) -> str:
        return self.haproxy.url if self.haproxy is not None else self.nodes[0].url

    def pids(self) -> dict[str, int]:
        """Component -> process (its children count with it: PostgreSQL's backends)."""
        found = {f"node{i}": n.pid for i, n in enumerate(self.nodes, 1) if n.alive()}
        if self.infra is not None:
            found.update(self.infra.pids())
        if self.haproxy is not None:
            found["haproxy"] = self.haproxy.process.pid
        return found

    def dead(self) -> list[str]:
        return [f"node{i}" for i, n in enumerate(self.nodes, 1) if not n.alive()]

    def stop(self) -> None:
        if self.haproxy is not None:
            self.haproxy.stop()
        for node in self.nodes:
            node.stop()
        shutil.rmtree(self.folder, ignore_errors=True)


def start_setup(name: str, infra: Infra | None, node_count: int) -> Setup:
    """`embedded` (one `twinlink up`, SQLite and the in-process bus), or `node_count` nodes
    on a new database of `infra` and its broker, behind haproxy when more than one."""
    folder = Path(tempfile.mkdtemp(prefix=f"twinlink-bench-{name}-"))
    setup = Setup(name, [], folder, infra)
    try:
        env: dict[str, str] = {}
        if infra is not None:
            assert infra.kafka is not None
            env = {
                "TWINLINK_STORE_URL": infra.new_database(),
                "TWINLINK_BUS_URL": f"kafka://{infra.kafka.bootstrap}",
                "TWINLINK_SECRET_KEY": infra.secret_key,  # the vault's key, the same on every node
            }
        first = Twinlink(folder / "node1", env=env)
        setup.nodes.append(first)
        first.start()  # alone first: it applies the migrations
        for i in range(2, node_count + 1):
            node = Twinlink(
                folder / f"node{i}",
                admin_token=first.admin_token,
                admin_password=first.admin_password,
                env=env,
            )
            setup.nodes.append(node)
            node.start()
        if node_count > 1:
            backends = [("127.0.0.1", n.port) for n in setup.nodes]
            setup.haproxy = start_haproxy(folder / "haproxy", 0, backends, _health_path(first))
            _wait_balanced(setup)
    except BaseException:
        setup.stop()
        raise
    return setup


def _health_path(node: Twinlink) -> str:
    """/readyz (the store and bus answer) where the server has it, else /healthz."""
    with httpx.Client(timeout=10) as client:
        return "/readyz" if client.get(f"{node.url}/readyz").status_code == 200 else "/healthz"


def _wait_balanced(setup: Setup, timeout_s: float = 30.0) -> None:
    """Until haproxy has seen every node healthy (it answers 503 before its checks pass)."""
    seen: set[str] = set()
    deadline = time.monotonic() + timeout_s
    with httpx.Client(timeout=5) as client:
        while time.monotonic() < deadline:
            with contextlib.suppress(httpx.TransportError):
                answer = client.get(f"{setup.entry}/healthz")
                if answer.status_code == 200:
                    seen.add(answer.headers.get("x-twinlink-node", ""))
            if len(seen) >= len(setup.nodes):
                return
            time.sleep(0.05)  # polling haproxy's real state, with a deadline
    raise RuntimeError(f"haproxy sent requests only to {sorted(seen)} within {timeout_s:g} s")


# httplog's termination state (who ended the session, in what state) and the timers after it
_STATE = re.compile(r" ([A-Za-z-]{4}) \d+/\d+/\d+/\d+/\d+ ")


def haproxy_aborts(log: Path, examples: int = 3) -> dict[str, object]:
    """Requests haproxy did not end normally (state other than `----`), by state: the first
    letter says who ended it (C client, S server, P/I haproxy), the second in which phase
    (R request, H headers, D data); see haproxy's "Session state at disconnection"."""
    states: Counter[str] = Counter()
    seen: list[str] = []
    with contextlib.suppress(OSError):
        for line in log.read_text(errors="replace").splitlines():
            m = _STATE.search(line)
            if m is None or m[1] == "----":
                continue
            states[m[1]] += 1
            if len(seen) < examples:
                seen.append(line[-300:])
    return {"states": dict(states), "examples": seen}
