"""The runs of lifecycle phases (deploy/runs.py): their records, claimed by the nodes.

A run is written `queued` before its process starts, with the node that will run it, or
without one when it waits for a node with its runner tags. Such a node claims it with one
conditional update (`state = 'queued' AND node IS NULL` in its WHERE), so of several nodes
polling for a queued run exactly one gets it. A run becomes `running` only from `queued`
(a run cancelled meanwhile is not started).
"""

from __future__ import annotations

from typing import Any, Protocol

import orjson

from twinlink.domain.runs import RunRecord

# The columns every backend reads, in the order `run_of` takes them.
COLUMNS = (
    "id, deployment_id, deployment, twin, phase, state, started_by, owner_id, created_ns,"
    " timeout_s, memory_mb, runner_tags, exit_code, started_ns, ended_ns, node, pid, error,"
    " token_id"
)
ACTIVE = ("queued", "running")


def run_of(row: Any) -> RunRecord:
    """A run from a row of COLUMNS (SQLite's or PostgreSQL's)."""
    return RunRecord(
        id=row[0], deployment_id=row[1], deployment=row[2], twin=row[3], phase=row[4],
        state=row[5], started_by=row[6], owner_id=row[7], created_ns=row[8],
        timeout_s=row[9], memory_mb=row[10], runner_tags=orjson.loads(row[11]),
        exit_code=row[12], started_ns=row[13], ended_ns=row[14], node=row[15], pid=row[16],
        error=row[17], token_id=row[18],
    )  # fmt: skip


class RunStore(Protocol):
    async def create_run(self, run: RunRecord) -> RunRecord:
        """Store `run` (its id ignored) and return it with the id the store gave it."""
        ...

    async def get_run(self, run_id: int) -> RunRecord | None: ...

    async def list_runs(
        self,
        *,
        deployment_id: int | None = None,
        states: tuple[str, ...] = (),
        limit: int = 100,
        before_id: int | None = None,
    ) -> list[RunRecord]:
        """Runs newest first: of one deployment (or all), in `states` (or any)."""
        ...

    async def claim_run(self, run_id: int, node: str) -> bool:
        """Take a queued run that no node has for `node`: True for the one caller that took
        it, False for everyone else (it was claimed, cancelled or is gone)."""
        ...

    async def set_run_token(self, run_id: int, token_id: int) -> None:
        """The run's scoped token, kept so a server that stopped mid-run revokes it."""
        ...

    async def mark_run_running(self, run_id: int, pid: int, now_ns: int) -> bool:
        """A queued run's process started (True); False when it is no longer queued."""
        ...

    async def end_run(
        self,
        run_id: int,
        state: str,
        exit_code: int | None,
        error: str | None,
        now_ns: int,
    ) -> bool:
        """End a run that has not ended (True), in `state`; an ended run stays as it was."""
        ...

    async def fail_interrupted_runs(
        self, node_like: str | None, error: str, now_ns: int
    ) -> list[RunRecord]:
        """Mark failed the runs left queued or running by a node that stopped: those whose
        node matches the SQL LIKE pattern `node_like`, or every one a node took when it is
        None (a queued run no node took waits on). They are returned as they were (their
        token ids, to revoke)."""
        ...
