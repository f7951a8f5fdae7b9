"""twinlink nodes of the local cluster: `python -m twinlink up` processes, each with its own
folder (its log, node.log) and port, sharing what the environment names (the store, the bus,
the secret key, the public URL)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import httpx

from twinlink.devcluster._process import dying_with_parent, stop_process
from twinlink.domain.errors import TwinlinkError

START_S = 120.0  # migrations on a fresh database, on a busy 2-core machine
STOP_S = 30.0  # a clean stop hands the node's leases and sessions over


class NodeError(TwinlinkError):
    """A node did not start."""


@dataclass
class Node:
    name: str
    port: int
    directory: Path
    process: subprocess.Popen[bytes]

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def log(self, tail: int = 3000) -> str:
        try:
            return (self.directory / "node.log").read_text(errors="replace")[-tail:]
        except OSError:
            return ""

    def stop(self) -> None:
        stop_process(self.process, signal.SIGTERM, STOP_S)


def launch_node(name: str, directory: Path, port: int, env: dict[str, str]) -> Node:
    """Start `twinlink up` on 127.0.0.1:`port` with `env` over this process's environment,
    without waiting for it (wait_serving)."""
    directory.mkdir(parents=True, exist_ok=True)
    command = [sys.executable, "-m", "twinlink", "up", "--host", "127.0.0.1",
               "--port", str(port), "--data-dir", str(directory)]  # fmt: skip
    with (directory / "node.log").open("ab") as log:
        process = subprocess.Popen(
            command,
            env={**os.environ, **env},
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            # SIGTERM is its clean stop: sessions closed, leases given back
            preexec_fn=dying_with_parent(signal.SIGTERM),
            process_group=0,  # a Ctrl-C in the terminal reaches the launcher alone
        )
    return Node(name, port, directory, process)


def wait_serving(node: Node) -> None:
    """Return once the node answers /healthz with 200; NodeError with its log's end when it
    exits or takes longer than START_S."""
    deadline = time.monotonic() + START_S
    with httpx.Client(timeout=5) as client:
        while time.monotonic() < deadline:
            if node.process.poll() is not None:
                raise NodeError(
                    f"{node.name} exited with {node.process.returncode} "
                    f"(log: {node.directory / 'node.log'}):\n{node.log()}"
                )
            try:
                if client.get(f"{node.url}/healthz").status_code == 200:
                    return
            except httpx.TransportError:
                pass  # not listening yet
            time.sleep(0.2)  # polling the node's real state, with a deadline
    node.stop()
    raise NodeError(f"{node.name} did not answer within {START_S:.0f} s:\n{node.log()}")
