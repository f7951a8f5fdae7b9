"""What a server that stopped left of its runs (deploy/runs.py's start): a run's process
group that outlived it, and whether the node that ran a run is gone."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
from pathlib import Path

from twinlink.domain.runs import RunRecord


def kill_leftover(run: RunRecord, work: Path) -> None:
    """A run's process group that outlived its server (killed with SIGKILL, it could not
    stop it): killed, if its leader is still that run's (a session leader working in the
    run's deployment's folder `work`: a pid used again by another process is left alone)."""
    if run.pid is None:
        return
    with contextlib.suppress(OSError):
        if (
            os.getpgid(run.pid) == run.pid
            and Path(f"/proc/{run.pid}/cwd").resolve() == work.resolve()
        ):
            os.killpg(run.pid, signal.SIGKILL)


def node_gone(node: str) -> bool:
    """Whether `node` (store/leases.py's `host:pid:random`) was a server of this host whose
    process has ended."""
    host, _, rest = node.partition(":")
    pid = rest.partition(":")[0]
    if host != socket.gethostname() or not pid.isdigit():
        return False
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # alive, another user's
        return False
    return False
