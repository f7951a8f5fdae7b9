"""Lifecycle runs: each phase of a deployment run as a supervised process (docs/runs.md).

A run is stored `queued` before anything starts, with a server-assigned id; a run of this
node then runs in its deployment's working folder (workdir.py: one kept across the
deployment's runs, brought to its package version by the target's `prepare`), with a token
scoped to the deployment's twin and its process (runner.py). It ends `succeeded`, `failed` or
`cancelled`, and its token is revoked, whatever happened. A run whose runner tags this node
lacks waits `queued` for a node that has them, which claims it (its target rebuilt by
`target_loader`).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import AsyncIterator, Awaitable, Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Protocol

from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthService
from twinlink.config import Settings
from twinlink.deploy import runlog, workdir
from twinlink.deploy.recovery import kill_leftover
from twinlink.deploy.runenv import run_environment
from twinlink.deploy.runner import Limits, Outcome, run_script
from twinlink.domain.errors import ForbiddenError, InvalidInputError, NotFoundError
from twinlink.domain.runs import PHASE_PATTERN, TWIN_SCOPE, RunRecord
from twinlink.store.leases import node_gone
from twinlink.store.runs import RunStore

log = logging.getLogger("twinlink.runs")
CLAIM_POLL_S = 1.0  # how often a node looks for queued runs it may take
INTERRUPTED = "the server stopped during the run"
Prepare = Callable[[Path], Awaitable[None]]


@dataclass(frozen=True, slots=True)
class PhaseSettings:
    """A phase's limits as a package gives them (twin.yaml `lifecycle:`); None: the default."""

    timeout_s: int | None = None
    memory_mb: int | None = None


@dataclass(slots=True)
class RunTarget:
    """What a run needs of its deployment; the deployment service makes one per run."""

    deployment_id: int
    deployment: str  # its name
    twin: str  # its twin's slug
    owner_id: int | None  # the user the run's token is for (the deployment's owner)
    # brings the deployment's working folder to its package version (workdir.prepare)
    prepare: Prepare
    params: dict[str, Any] = field(default_factory=dict)
    device_tokens: dict[str, str] = field(default_factory=dict)  # device name -> token
    # twin.yaml's `lifecycle:` block: phase (or "default") -> its settings
    lifecycle: Mapping[str, PhaseSettings] = field(default_factory=dict)
    runner_tags: list[str] = field(default_factory=list)
    # The phases the package has scripts for, when known: a phase not among them is refused
    # before a run is made. None: found out in the working dir.
    phases: frozenset[str] | None = None

    def limits(self, phase: str, defaults: Limits) -> Limits:
        given = self.lifecycle.get(phase, PhaseSettings())
        default = self.lifecycle.get("default", PhaseSettings())
        timeout = _first(given.timeout_s, default.timeout_s, defaults.timeout_s)
        memory = _first(given.memory_mb, default.memory_mb, defaults.memory_mb)
        return Limits(timeout, memory)


def _first(*values: int | None) -> int:
    return next(v for v in values if v is not None)


TargetLoader = Callable[[RunRecord], Awaitable[RunTarget]]


class Deployments(Protocol):
    """The deployments' service as the runs see it: it starts runs, and rebuilds the target
    of a run that another node queued."""

    runs: Any

    async def target_of(self, deployment_id: int) -> RunTarget: ...


@dataclass(frozen=True, slots=True)
class RunSettings:
    root: Path  # data_dir/runs: the runs' logs
    url: str  # the server's URL, as runs reach it
    node: str  # this node, in the runs it runs
    tags: frozenset[str] = frozenset()  # this node's runner tags
    script_runners: Literal["admins", "owners"] = "admins"
    defaults: Limits = field(default_factory=lambda: Limits(3600, 2048))
    # Several nodes share the store: at start, only the unfinished runs of this host's
    # nodes that are gone are this node's to fail (not every unfinished run is).
    shared: bool = False
    # The deployments' working folders (workdir.py); None: `deployments` beside `root`.
    folders: Path | None = None

    def folder(self, deployment_id: int) -> Path:
        return workdir.folder(self.folders or self.root.parent / "deployments", deployment_id)


class RunService:
    @classmethod
    def configured(
        cls, settings: Settings, store: RunStore, auth: AuthService, node: str, shared: bool
    ) -> RunService:
        """The service as the settings have it: data_dir/runs, runner tags, limits."""
        tags = frozenset(t.strip() for t in settings.runner_tags.split(",") if t.strip())
        defaults = Limits(settings.run_default_timeout_s, settings.run_default_memory_mb)
        config = RunSettings(settings.data_dir / "runs", settings.base_url, node, tags,
                             settings.script_runners, defaults, shared,
                             settings.data_dir / "deployments")  # fmt: skip
        return cls(store, auth, config)

    def __init__(self, store: RunStore, auth: AuthService, settings: RunSettings) -> None:
        self.store = store
        self.auth = auth
        self.settings = settings
        # Set by the deployments' service: rebuilds the target of a run another node queued.
        self.target_loader: TargetLoader | None = None
        self._tasks: dict[int, asyncio.Task[None]] = {}  # the runs this node runs
        # One prepare of a deployment's folder at a time (its runs share it).
        self._folder_locks: dict[int, asyncio.Lock] = {}
        self._poller: asyncio.Task[None] | None = None

    def serve(self, deployments: Deployments | None) -> RunService:
        """Run the lifecycle phases of `deployments` (None: there are none here)."""
        if deployments is not None:
            deployments.runs = self
            self.target_loader = lambda run: deployments.target_of(run.deployment_id)
        return self

    # -- life of the service ---------------------------------------------------------------

    async def open(self) -> None:
        self.settings.root.mkdir(parents=True, exist_ok=True)
        failed = await self._fail_interrupted()
        for run in failed:
            await asyncio.to_thread(kill_leftover, run, self.settings.folder(run.deployment_id))
            if run.token_id is not None:
                await self.auth.revoke_run_token(run.token_id)
            await asyncio.to_thread(self._note, run.id, f"failed: {INTERRUPTED}")
        if failed:
            log.warning("runs interrupted by a stop", extra={
                "event": "runs_interrupted", "runs": [run.id for run in failed]})  # fmt: skip
        self._poller = asyncio.create_task(self._claim_loop(), name="runs-claim")

    async def _fail_interrupted(self) -> list[RunRecord]:
        """Mark failed the runs a server that stopped left unfinished: on the only node, all
        of them; with a shared store, those of this host's nodes whose process is gone (a
        queued run no node has claimed waits on)."""
        now = time.time_ns()
        if not self.settings.shared:
            return await self.store.fail_interrupted_runs(None, INTERRUPTED, now)
        active = await self.store.list_runs(states=("queued", "running"), limit=10_000)
        gone = [run for run in active if run.node is not None and node_gone(run.node)]
        return [run for run in gone if await self.store.end_run(run.id, "failed", None,
                                                                 INTERRUPTED, now)]  # fmt: skip

    async def close(self) -> None:
        """Cancel the runs of this node (their process groups killed, marked cancelled)."""
        if self._poller is not None:
            self._poller.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._poller
            self._poller = None
        tasks = list(self._tasks.values())
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    # -- starting and stopping runs --------------------------------------------------------

    def check_may_run(self, principal: Principal, owner_id: int | None) -> None:
        if principal.is_admin:
            return
        owner = principal.user is not None and principal.user.id == owner_id
        if self.settings.script_runners == "owners" and owner:
            return
        who = "admins" if self.settings.script_runners == "admins" else "admins and its owner"
        raise ForbiddenError(
            f"only {who} may run a deployment's lifecycle scripts "
            "(setting script_runners, TWINLINK_SCRIPT_RUNNERS)"
        )

    async def start(self, principal: Principal, target: RunTarget, phase: str) -> RunRecord:
        """Store a run of `phase` and start it here, or leave it queued for a node with its
        runner tags. The run as stored (`queued`)."""
        self.check_may_run(principal, target.owner_id)
        if not PHASE_PATTERN.fullmatch(phase):
            raise InvalidInputError(
                f"a phase is a lifecycle script's name ({PHASE_PATTERN.pattern}), not {phase!r}"
            )
        if target.phases is not None and phase not in target.phases:
            has = ", ".join(sorted(target.phases)) or "none"
            raise NotFoundError(
                f"the package of deployment {target.deployment!r} has no lifecycle/{phase} "
                f"script (it has: {has})"
            )
        limits = target.limits(phase, self.settings.defaults)
        here = set(target.runner_tags) <= self.settings.tags
        assert principal.user is not None
        run = await self.store.create_run(
            RunRecord(
                id=0, deployment_id=target.deployment_id, deployment=target.deployment,
                twin=target.twin, phase=phase, state="queued", started_by=principal.user.id,
                owner_id=target.owner_id, created_ns=time.time_ns(), timeout_s=limits.timeout_s,
                memory_mb=limits.memory_mb, runner_tags=sorted(target.runner_tags),
                node=self.settings.node if here else None,
            )
        )  # fmt: skip
        if here:
            self._launch(run, target)
        else:
            log.info("run waits for a node with its tags", extra={
                "event": "run_queued", "run": run.id, "tags": run.runner_tags})  # fmt: skip
        return run

    async def cancel(self, principal: Principal, run_id: int) -> RunRecord:
        """Cancel a run (a no-op for one that has ended); the run as it is afterwards."""
        run = await self.get(run_id)
        self.check_may_run(principal, run.owner_id)
        await self._cancel(run)
        return await self.get(run_id)

    async def cancel_phase(self, deployment_id: int, phase: str) -> list[int]:
        """Cancel every unfinished run of `phase` of a deployment (stop ends `execute` so);
        the ids of those cancelled. Rights are the caller's to check."""
        runs = await self.store.list_runs(
            deployment_id=deployment_id, states=("queued", "running"), limit=1000
        )
        chosen = [run for run in runs if run.phase == phase]
        for run in chosen:
            await self._cancel(run)
        return [run.id for run in chosen]

    async def _cancel(self, run: RunRecord) -> None:
        task = self._tasks.get(run.id)
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
        elif not run.ended:  # queued, or another node's: the record says so, and that node
            # stops the run at its next round (_stop_cancelled), or never starts it
            await self.store.end_run(run.id, "cancelled", None, "cancelled", time.time_ns())

    async def wait(self, run_id: int, timeout_s: float | None = None) -> RunRecord:
        """The run once it has ended: a run of this node is awaited (its task ends with it),
        another node's looked at every CLAIM_POLL_S. TimeoutError after `timeout_s` (None:
        no bound)."""

        async def ended() -> RunRecord:
            task = self._tasks.get(run_id)
            if task is not None:
                await asyncio.wait({task})  # never cancels the run itself
            while not (run := await self.get(run_id)).ended:
                await asyncio.sleep(CLAIM_POLL_S)
                if (task := self._tasks.get(run_id)) is not None:  # claimed here meanwhile
                    await asyncio.wait({task})
            return run

        return await asyncio.wait_for(ended(), timeout_s)

    async def remove_folder(self, deployment_id: int) -> None:
        """Remove the deployment's working folder on this node (a terminated deployment's,
        once its `clean` has run)."""
        lock = self._folder_locks.setdefault(deployment_id, asyncio.Lock())
        async with lock:
            await asyncio.to_thread(
                workdir.remove, self.settings.folder(deployment_id).parent.parent, deployment_id
            )
        self._folder_locks.pop(deployment_id, None)

    # -- reading runs -----------------------------------------------------------------------

    async def get(self, run_id: int) -> RunRecord:
        run = await self.store.get_run(run_id)
        if run is None:
            raise NotFoundError(f"no run {run_id}")
        return run

    async def runs(
        self, deployment_id: int | None = None, limit: int = 100, before_id: int | None = None
    ) -> list[RunRecord]:
        return await self.store.list_runs(
            deployment_id=deployment_id, limit=limit, before_id=before_id
        )

    def log(self, run_id: int, offset: int = 0) -> AsyncIterator[bytes]:
        """The run's log from byte `offset`, as much as is written now."""
        return runlog.read_range(runlog.log_path(self.settings.root, run_id), offset)

    def follow(self, run_id: int, offset: int = 0) -> AsyncIterator[bytes]:
        """The run's log from byte `offset` as it is written, until the run has ended."""

        async def ended() -> bool:
            if run_id in self._tasks:
                return False
            return (await self.get(run_id)).ended

        return runlog.follow(runlog.log_path(self.settings.root, run_id), offset, ended)

    # -- running ----------------------------------------------------------------------------

    def _launch(self, run: RunRecord, target: RunTarget) -> None:
        task = asyncio.create_task(self._run(run, target), name=f"run-{run.id}")
        self._tasks[run.id] = task
        task.add_done_callback(lambda _: self._tasks.pop(run.id, None))

    async def _run(self, run: RunRecord, target: RunTarget) -> None:
        work = self.settings.folder(run.deployment_id)
        token_id: int | None = None
        outcome = Outcome("failed", None, "the run did not start")
        try:
            async with self._folder_locks.setdefault(run.deployment_id, asyncio.Lock()):
                await target.prepare(work)
            script = work / "lifecycle" / run.phase
            if not script.is_file():
                outcome = Outcome("failed", None, f"the package has no lifecycle/{run.phase}")
                return
            if target.owner_id is None:
                outcome = Outcome("failed", None, "the deployment has no owner to run as")
                return
            issued = await self.auth.issue_run_token(
                target.owner_id, f"run {run.id} ({run.deployment} {run.phase})",
                TWIN_SCOPE + target.twin,
            )  # fmt: skip
            token_id = issued.record.id
            await self.store.set_run_token(run.id, token_id)
            env = run_environment(
                work=work, url=self.settings.url, token=issued.token, twin=target.twin,
                deployment=target.deployment, phase=run.phase, run_id=run.id,
                params=target.params, device_tokens=target.device_tokens,
            )  # fmt: skip

            async def started(pid: int) -> bool:
                return await self.store.mark_run_running(run.id, pid, time.time_ns())

            outcome = await run_script(
                script, work, env, runlog.log_path(self.settings.root, run.id),
                Limits(run.timeout_s, run.memory_mb), started,
            )  # fmt: skip
        except asyncio.CancelledError:
            outcome = Outcome("cancelled", None, "cancelled")
            raise
        except Exception as err:  # a failed prepare (a package gone), a full disk, ...
            log.exception("run failed", extra={"event": "run_failed", "run": run.id})
            outcome = Outcome("failed", None, f"the run could not be prepared: {err}")
        finally:
            await asyncio.shield(self._finish(run, outcome, token_id))

    async def _finish(self, run: RunRecord, outcome: Outcome, token_id: int | None) -> None:
        """Whatever happened: the token revoked, the end noted in the log, then in the
        record (a follower that sees the end has the whole log). The working folder is the
        deployment's, and stays."""
        if token_id is not None:
            await self.auth.revoke_run_token(token_id)
        text = outcome.state + (f": {outcome.error}" if outcome.error else "")
        await asyncio.to_thread(self._note, run.id, text)
        await self.store.end_run(
            run.id, outcome.state, outcome.exit_code, outcome.error, time.time_ns()
        )
        log.info("run ended", extra={"event": "run_ended", "run": run.id, "state": outcome.state,
                                     "exit_code": outcome.exit_code})  # fmt: skip

    def _note(self, run_id: int, text: str) -> None:
        runlog.append_line(runlog.log_path(self.settings.root, run_id), text)

    async def _claim_loop(self) -> None:
        """Take the queued runs this node has the tags for and nobody has claimed; with a
        shared store, stop this node's runs that another node cancelled."""
        while True:
            await asyncio.sleep(CLAIM_POLL_S)
            try:
                if self.settings.shared:
                    await self._stop_cancelled()
                if self.target_loader is not None:
                    await self._claim_round(self.target_loader)
            except Exception:
                log.exception("claiming runs failed", extra={"event": "runs_claim_failed"})

    async def _stop_cancelled(self) -> None:
        for run_id, task in list(self._tasks.items()):
            run = await self.store.get_run(run_id)
            if run is not None and run.ended and not task.done():
                task.cancel()  # its process group stopped; its record stays as it was ended

    async def _claim_round(self, loader: TargetLoader) -> None:
        queued = await self.store.list_runs(states=("queued",), limit=100)
        for run in reversed(queued):  # oldest first
            if run.node is not None or not set(run.runner_tags) <= self.settings.tags:
                continue
            if not await self.store.claim_run(run.id, self.settings.node):
                continue
            try:
                target = await loader(run)
            except Exception as err:
                await self.store.end_run(
                    run.id, "failed", None, f"the run's deployment could not be loaded: {err}",
                    time.time_ns(),
                )  # fmt: skip
                continue
            self._launch(run, target)
