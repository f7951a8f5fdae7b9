"""Lifecycle phases run one after another in the background: a terminated deployment's
`terminate` and then `clean`. The request that terminates does not wait for scripts that may
run for minutes; the runs are recorded, with their logs, as any other."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any, Protocol

from twinlink.auth.rights import Principal
from twinlink.deploy.runs import RunTarget
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


class PhaseChains:
    def __init__(self, runs: PhaseRuns) -> None:
        self.runs = runs
        self._tasks: set[asyncio.Task[None]] = set()

    def start(
        self,
        principal: Principal,
        target: RunTarget,
        phases: list[str],
        then: Callable[[], Awaitable[None]],
    ) -> None:
        """Run `phases` in order, each once the one before has ended (however it ended), then
        call `then` (whatever happened)."""
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
