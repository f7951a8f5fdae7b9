"""A deployment's lifecycle phases, as runs of the runs' service (runs.py): started when the
package has their script, refused up front to who may not run scripts, and the steps of a
terminate (its `terminate` script, the resources removed, `clean`, the working folder removed)
taken one after another in the background (the request that terminates does not wait for
scripts that may run for minutes)."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any, Protocol

from twinlink.auth.rights import Principal
from twinlink.deploy.loading import Library, Loaded
from twinlink.deploy.runs import RunTarget
from twinlink.deploy.targets import run_target
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import TwinlinkError

log = logging.getLogger("twinlink.deploy")
# How long past its own timeout a run the next step waits for may take to end (the grace a
# stop gives it, its folder's preparing); a run without a timeout is waited for as long as
# it runs.
WAIT_MARGIN_S = 60.0
# A step of a chain: a phase's run (its name), or something the platform does.
Step = str | Callable[[], Awaitable[None]]


class PhaseRuns(Protocol):
    """The lifecycle runs (deploy/runs.py's RunService): a phase's script started, cancelled
    or looked at, and who may start one."""

    def check_may_run(self, principal: Principal, owner_id: int | None) -> None: ...
    async def start(self, principal: Principal, target: RunTarget, phase: str) -> Any: ...
    async def cancel_phase(self, deployment_id: int, phase: str) -> Any: ...
    async def get(self, run_id: int) -> Any: ...
    async def wait(self, run_id: int, timeout_s: float | None = None) -> Any: ...
    async def remove_folder(self, deployment_id: int) -> None: ...


class Phases:
    def __init__(self, library: Library | None) -> None:
        self.library = library
        self.runs: PhaseRuns | None = None  # None: no runs on this server (phases skipped)
        self._tasks: set[asyncio.Task[None]] = set()

    @property
    def ready(self) -> bool:
        return self.runs is not None and self.library is not None

    def target(
        self, record: DeploymentRecord, loaded: Loaded, device_tokens: dict[str, str]
    ) -> RunTarget:
        if self.library is None:
            raise TwinlinkError("the library is not available on this server")
        return run_target(self.library, record, loaded, device_tokens)

    def check(
        self, principal: Principal, owner_id: int | None, loaded: Loaded | None, *phases: str
    ) -> None:
        """Refuse before anything is changed when a phase the request would start may not
        be run by the caller (setting script_runners)."""
        if loaded is None or self.runs is None:
            return
        if any(loaded.has_phase(p) for p in phases):
            self.runs.check_may_run(principal, owner_id)

    async def start(
        self,
        principal: Principal,
        record: DeploymentRecord,
        loaded: Loaded | None,
        phase: str,
        device_tokens: dict[str, str],
    ) -> None:
        """Start the phase's run when the package has its script."""
        if self.runs is not None and loaded is not None and loaded.has_phase(phase):
            await self.runs.start(principal, self.target(record, loaded, device_tokens), phase)

    async def cancel(self, deployment_id: int, phase: str) -> None:
        if self.runs is not None:
            await self.runs.cancel_phase(deployment_id, phase)

    def in_turn(
        self,
        principal: Principal,
        target: RunTarget,
        steps: list[Step],
        then: Callable[[], Awaitable[None]],
    ) -> None:
        """Take `steps` in order in the background, each once the one before has ended
        (however it ended: a failed script does not stop the steps after it), then call
        `then` (whatever happened)."""
        task = asyncio.create_task(self._chain(principal, target, steps, then))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _chain(
        self,
        principal: Principal,
        target: RunTarget,
        steps: list[Step],
        then: Callable[[], Awaitable[None]],
    ) -> None:
        try:
            for step in steps:
                try:
                    await (self._run(principal, target, step) if isinstance(step, str) else step())
                except (TwinlinkError, TimeoutError) as err:
                    name = step if isinstance(step, str) else getattr(step, "__name__", "a step")
                    log.warning("deployment %s: %s did not end well: %s", target.deployment,
                                name, err or "it did not end in time",
                                extra={"event": "phases_failed"})  # fmt: skip
        finally:
            await then()

    async def _run(self, principal: Principal, target: RunTarget, phase: str) -> None:
        """Run `phase` and wait until it has ended (its own timeout and a margin at most)."""
        assert self.runs is not None
        run = await self.runs.start(principal, target, phase)
        timeout = run.timeout_s + WAIT_MARGIN_S if run.timeout_s else None
        await self.runs.wait(run.id, timeout)

    async def remove_folder(self, deployment_id: int) -> None:
        if self.runs is not None:
            await self.runs.remove_folder(deployment_id)

    async def close(self) -> None:
        """Stop waiting (the runs themselves are the runs service's to stop)."""
        for task in list(self._tasks):
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
