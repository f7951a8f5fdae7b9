"""What a server that stopped without stopping its co-simulations left: their workers, and
on a store nodes share, which nodes are gone.

A worker runs in a session of its own (jobs.py), so a server killed with SIGKILL leaves it
running; its pid is noted in its results folder (`worker.pid`, its working directory), and
the next start kills its process group if that pid is still that worker's. A node
(store/leases.py's `host:pid:random`) is gone when it is of this host and its process has
ended (store/leases.py node_gone, which the lifecycle runs use too); another host's nodes are
that host's to judge."""

from __future__ import annotations

import contextlib
import os
import signal
from pathlib import Path

from twinlink.store.leases import node_gone

PID_FILE = "worker.pid"


def note_worker(results: Path, pid: int | None) -> None:
    if pid is not None:
        (results / PID_FILE).write_text(f"{pid}\n", encoding="ascii")


def kill_leftover(results: Path) -> None:
    """Kill the worker noted in `results` (and what it started), if it still runs there: a
    session leader working in that folder (a pid used again by another process is left)."""
    with contextlib.suppress(OSError, ValueError):
        pid = int((results / PID_FILE).read_text(encoding="ascii"))
        if os.getpgid(pid) == pid and Path(f"/proc/{pid}/cwd").resolve() == results.resolve():
            os.killpg(pid, signal.SIGKILL)


def gone_nodes(nodes: list[str]) -> list[str]:
    return sorted({node for node in nodes if node_gone(node)})
