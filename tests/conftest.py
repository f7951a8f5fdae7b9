"""Shared fixtures. Integration tests start a real `twinlink up` process on a random
loopback port and talk to it with a real HTTP client; the process is stopped afterwards.

tests/_hygiene.py (loaded below) fails a test that leaves a task, thread or child process
running, an integration module without its marker, and a unit test that compiles."""

from __future__ import annotations

import os
import secrets
import signal
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import httpx
import pytest

pytest_plugins = ["tests._hygiene"]

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Server:
    url: str
    data_dir: Path
    admin_token: str
    admin_password: str
    process: subprocess.Popen[bytes]
    output: list[str] = field(default_factory=list)
    reader: threading.Thread | None = None

    def client(self, token: str | None = None) -> httpx.Client:
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        return httpx.Client(base_url=self.url, headers=headers, timeout=30)

    @property
    def admin(self) -> httpx.Client:
        return self.client(self.admin_token)

    def log(self) -> str:
        return "".join(self.output)


def start_server(
    data_dir: Path,
    extra_env: dict[str, str] | None = None,
    *,
    port: int | None = None,
    token: str | None = None,
    password: str | None = None,
) -> Server:
    port = port or free_port()
    token = token or "tl_test_" + secrets.token_urlsafe(24)
    password = password or secrets.token_urlsafe(12)
    env = {
        **os.environ,
        "TWINLINK_ADMIN_TOKEN": token,
        "TWINLINK_ADMIN_PASSWORD": password,
        "TWINLINK_LOG_LEVEL": "warning",
        "TWINLINK_MQTT_PORT": "0",  # servers of tests run side by side: any free port
        **(extra_env or {}),
    }
    proc = subprocess.Popen(
        [sys.executable, "-m", "twinlink", "up", "--port", str(port), "--data-dir", str(data_dir)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )
    server = Server(f"http://127.0.0.1:{port}", data_dir, token, password, proc)
    ready = threading.Event()

    def pump() -> None:
        assert proc.stdout is not None
        for raw in proc.stdout:
            line = raw.decode(errors="replace")
            server.output.append(line)
            if line.startswith("twinlink serving at"):
                ready.set()
        ready.set()

    server.reader = threading.Thread(target=pump, daemon=True)
    server.reader.start()
    # The server prints a line when it serves; wait on that event, not on a fixed sleep.
    if not ready.wait(timeout=60) or proc.poll() is not None:
        stop_server(server)
        raise RuntimeError(f"twinlink did not start:\n{server.log()}")
    with httpx.Client() as c:
        status = c.get(f"{server.url}/healthz").status_code
    if status != 200:  # stop it: a server left running would outlive the test session
        stop_server(server)
        raise RuntimeError(f"twinlink answered /healthz with {status}:\n{server.log()}")
    return server


def restart_server(server: Server, extra_env: dict[str, str] | None = None) -> Server:
    """Start the server again on the same port and data dir (after a stop or a kill)."""
    port = int(server.url.rsplit(":", 1)[1])
    return start_server(
        server.data_dir,
        extra_env,
        port=port,
        token=server.admin_token,
        password=server.admin_password,
    )


def stop_server(server: Server) -> None:
    if server.process.poll() is None:
        server.process.send_signal(signal.SIGTERM)
        try:
            server.process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            server.process.kill()
            server.process.wait()
    if server.reader is not None:
        server.reader.join(timeout=10)
    if server.process.stdout is not None:
        server.process.stdout.close()


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A fresh server with an empty data dir, shared by the tests of one module."""
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


FMU_SOURCES = {
    "tingen": EXAMPLES / "tingen" / "fmu",
    "tingen3": EXAMPLES / "tingen" / "fmu3",
    "crash": ROOT / "tests" / "fmus" / "crash",
    "leak": ROOT / "tests" / "fmus" / "leak",
    "status": ROOT / "tests" / "fmus" / "status",
    "stair": ROOT / "tests" / "fmus" / "stair" / "fmi2",
    "stair3": ROOT / "tests" / "fmus" / "stair" / "fmi3",
    "msd_mass": ROOT / "tests" / "fmus" / "msd_mass",
    "msd_spring": ROOT / "tests" / "fmus" / "msd_spring",
    "ticks": ROOT / "tests" / "fmus" / "ticks",
    "msd_mass_me": ROOT / "tests" / "fmus" / "msd_mass_me",
    "incubator_plant": ROOT / "tests" / "fmus" / "incubator_plant",
    "incubator_controller": ROOT / "tests" / "fmus" / "incubator_controller",
    "incubator_kalman": ROOT / "tests" / "fmus" / "incubator_kalman",
    "chain_mass": ROOT / "tests" / "fmus" / "chain_mass",
    "maxstep": ROOT / "tests" / "fmus" / "maxstep",
    "ticks3": ROOT / "tests" / "fmus" / "ticks3",
}


class FmuFiles:
    """Builds the FMUs the tests use from their C sources, each at most once per session."""

    def __init__(self, out_dir: Path) -> None:
        self.out_dir = out_dir
        self.built: dict[str, Path] = {}

    def __call__(self, name: str) -> Path:
        from twinlink.processors.fmubuild import build_fmu

        if name not in FMU_SOURCES:
            raise ValueError(f"unknown test FMU {name!r}; one of {sorted(FMU_SOURCES)}")
        if name not in self.built:
            self.built[name] = build_fmu(FMU_SOURCES[name], self.out_dir / f"{name}.fmu")
        return self.built[name]


@pytest.fixture(scope="session")
def fmu_files(tmp_path_factory: pytest.TempPathFactory) -> FmuFiles:
    """`fmu_files(name)` is the path of the built FMU: "tingen" (FMI 2.0, examples/tingen/fmu),
    "tingen3" (FMI 3.0, examples/tingen/fmu3), or "crash", "leak", "status", "stair" (FMI 2.0)
    and "stair3" (FMI 3.0) (tests/fmus), the co-simulated mass-spring-damper pair
    "msd_mass" and "msd_spring", the Incubator's "incubator_plant", "incubator_controller" and
    "incubator_kalman", and "chain_mass", one mass of a chain (FMI 2.0); "msd_mass_me" is
    msd_mass as model exchange only (FMI 2.0); "ticks" discards every step passing a tick;
    "maxstep" tells the time to its next tick through fmi2GetMaxStepsize; "ticks3" (FMI 3.0)
    returns early from a step passing a whole second, without terminating."""
    return FmuFiles(tmp_path_factory.mktemp("fmus"))
