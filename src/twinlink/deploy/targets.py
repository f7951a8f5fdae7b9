"""What a lifecycle run needs of its deployment (runs.py's RunTarget): the package's files and
its assets for the deployment's working folder (workdir.py), the parameters, the device
tokens, the phases' limits."""

from __future__ import annotations

import json
from pathlib import Path

from twinlink.deploy import workdir
from twinlink.deploy.loading import Library, Loaded
from twinlink.deploy.runs import PhaseSettings, RunTarget
from twinlink.domain.deployments import DeploymentRecord


def run_target(
    library: Library, record: DeploymentRecord, loaded: Loaded, device_tokens: dict[str, str]
) -> RunTarget:
    async def materialize(dest: Path) -> None:
        """The package's files at the top, each asset under assets/<alias>/."""
        await library.materialize(loaded.resolved, dest)
        for alias, resolved in loaded.assets.items():
            await library.materialize(resolved, dest / "assets" / alias)

    # The versions the folder is to hold: a reconfigure to another package or asset version
    # changes it, and the next run's folder is brought to it.
    key = json.dumps([loaded.pinned, sorted((a, str(r.pinned)) for a, r in loaded.assets.items())])

    async def prepare(work: Path) -> None:
        await workdir.prepare(work, key, materialize)

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
            phase: PhaseSettings(limits.timeout_s, limits.memory_mb)  # None: not given
            for phase, limits in package.lifecycle.items()
        },
        runner_tags=list(package.runner_tags),
        phases=loaded.phases(),
    )
