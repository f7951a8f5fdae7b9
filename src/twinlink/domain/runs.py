"""Lifecycle runs (DTaaS): one run of one phase script of a deployment, as a durable record.

A run is stored `queued` before its process starts (its id is the store's, never guessed),
is `running` on one node with its process id, and ends `succeeded`, `failed` or
`cancelled` with its exit code and time. Its log is a file of its own (deploy/runlog.py).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Literal

RunState = Literal["queued", "running", "succeeded", "failed", "cancelled"]
RUN_STATES: tuple[RunState, ...] = ("queued", "running", "succeeded", "failed", "cancelled")
ENDED_STATES: frozenset[str] = frozenset({"succeeded", "failed", "cancelled"})
# The DTaaS phases; a package may hold scripts of other names, which run the same way.
PHASES = ("create", "execute", "analyze", "evolve", "save", "terminate", "clean")
# A phase names a file under lifecycle/: no path separators, nothing hidden.
PHASE_PATTERN = re.compile(r"^[a-z][a-z0-9_-]{0,31}$")
# The prefix of a run token's scope: `twin:<slug>` (auth/scopes.py).
TWIN_SCOPE = "twin:"


@dataclass(slots=True)
class RunRecord:
    id: int
    deployment_id: int
    deployment: str  # the deployment's name at the run's start
    twin: str  # the deployment's twin (slug)
    phase: str
    state: RunState
    started_by: int | None  # the user who asked for the run
    created_ns: int
    owner_id: int | None = None  # the deployment's owner: whose rights its token has
    timeout_s: int = 0  # 0: no time limit
    memory_mb: int = 0  # 0: no memory limit
    runner_tags: list[str] = field(default_factory=list)  # a node needs all of them
    exit_code: int | None = None
    started_ns: int | None = None
    ended_ns: int | None = None
    node: str | None = None  # the node that runs (ran) it
    pid: int | None = None
    error: str | None = None
    token_id: int | None = None  # its scoped token, revoked when it ends

    @property
    def ended(self) -> bool:
        return self.state in ENDED_STATES
