"""A deployment's lifecycle phases, as runs of the runs' service (runs.py): started when the
package has their script, refused up front to who may not run scripts, and a terminated
deployment's `terminate` then `clean` run one after another in the background (the request
that terminates does not wait for scripts that may run for minutes)."""

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
POLL_S = 0.5  # how often a run that the next phase waits for is looked at


class PhaseRuns(Protocol):
    """The lifecycle runs (deploy/runs.py's RunService): a phase's script started, cancelled
    or looked at, and who may start one."""

    def check_may_run(self, principal: Principal, owner_id: int | None) -> None: ...
    async def start(self, principal: Principal, target: RunTarget, phase: str) -> Any: ...
    async def cancel_phase(self, deployment_id: int, phase: str) -> Any: ...
    async def get(self, run_id: int) -> Any: ...


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
        phases: list[str],
        then: Callable[[], Awaitable[None]],
    ) -> None:
        """Run `phases` in order in the background, each once the one before has ended
        (however it ended), then call `then` (whatever happened)."""
        task = asyncio.create_task(self._chain(principal, target, phases, then))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _chain(
        self,
        principal: Principal,
        target: RunTarget,
        phases: list[str],
        then: Callable[[], Awaitable[None]],
    ) -> None:
        try:
            for phase in phases:
                assert self.runs is not None
                run = await self.runs.start(principal, target, phase)
                while not (await self.runs.get(run.id)).ended:
                    await asyncio.sleep(POLL_S)
        except TwinlinkError as err:
            log.warning("deployment %s: the %s phases stopped: %s", target.deployment,
                        ", ".join(phases), err, extra={"event": "phases_failed"})  # fmt: skip
        finally:
            await then()

    async def close(self) -> None:
        """Stop waiting (the runs themselves are the runs service's to stop)."""
        for task in list(self._tasks):
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
