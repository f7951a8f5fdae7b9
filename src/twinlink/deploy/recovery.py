"""What a server that stopped left of its runs (deploy/runs.py's start): a run's process
group that outlived it, and whether the node that ran a run is gone."""

from __future__ import annotations

import contextlib
import os
import signal
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
