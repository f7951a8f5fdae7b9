"""What a lifecycle run needs of its deployment (runs.py's RunTarget): the package's files and
its assets for the working dir, the parameters, the device tokens, the phases' limits."""

from __future__ import annotations

from pathlib import Path

from twinlink.deploy.loading import Library, Loaded
from twinlink.deploy.runs import PhaseSettings, RunTarget
from twinlink.domain.deployments import DeploymentRecord


def run_target(
    library: Library, record: DeploymentRecord, loaded: Loaded, device_tokens: dict[str, str]
) -> RunTarget:
    async def prepare(work: Path) -> None:
        """The package's files at the top of the working dir, each asset under
        assets/<alias>/."""
        await library.materialize(loaded.resolved, work)
        for alias, resolved in loaded.assets.items():
            await library.materialize(resolved, work / "assets" / alias)

    package = loaded.package
    return RunTarget(
        deployment_id=record.id,
        deployment=record.name,
        twin=record.twin,
        owner_id=record.created_by,
        prepare=prepare,
        params=dict(loaded.parameters),  # with the secret ones
        device_tokens=device_tokens,
        lifecycle={
            phase: PhaseSettings(limits.timeout_s, limits.memory_mb)
            for phase, limits in package.lifecycle.items()
        },
        runner_tags=list(package.runner_tags),
        phases=loaded.phases(),
    )
