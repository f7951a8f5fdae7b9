"""A deployment's end, as DTaaS orders it (docs/deployments.md): the package's `terminate`
script stops what the twin runs with everything still there (its device tokens work, the twin
is there), then the platform removes what the deployment made (the twin only with purge),
then `clean` tidies the working folder, which is then removed, and the deployment's holds on
library versions are released last (the scripts had their files).

The deployment is `terminated` at once, so nothing starts it again; the scripts and what
waits for them go on in the background (deploy/phases.py's chain). A terminate script that
fails is logged in its run and the removal goes on. A server stopped before the removal
leaves the resources: terminating the deployment again removes them."""

from __future__ import annotations

import asyncio
from typing import Protocol

from twinlink.auth.rights import Principal
from twinlink.deploy.apply import Parts
from twinlink.deploy.loading import Loaded
from twinlink.deploy.phases import Phases, Step
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import ConflictError
from twinlink.store.base import MetadataStore


class DeploymentService(Protocol):
    """What a terminate uses of the deployments' service (service.py)."""

    store: MetadataStore
    parts: Parts
    phases: Phases
    lock: asyncio.Lock

    async def pinned(self, record: DeploymentRecord) -> Loaded | None: ...
    async def save(self, record: DeploymentRecord) -> None: ...
    async def release(self, record: DeploymentRecord) -> None: ...
    def device_tokens(self, record: DeploymentRecord) -> dict[str, str]: ...


async def terminate(
    svc: DeploymentService, principal: Principal, record: DeploymentRecord, purge: bool
) -> DeploymentRecord:
    """Terminate `record` (its changer checked by the caller); the record as it is then. A
    terminated deployment is terminated again only to remove what is left of it."""
    left = [e for e in record.journal if purge or e["type"] != "twin"]
    if record.state == "terminated" and not left:
        raise ConflictError(f"deployment {record.name!r} is terminated; create it again")
    loaded = await svc.pinned(record)
    # The scripts run for a deployment that was made (not a planned or failed one, nor one
    # terminated again to remove what a stopped server left).
    made = record.state in ("created", "running", "stopped")
    ending = [p for p in ("terminate", "clean") if made and loaded and loaded.has_phase(p)]
    svc.phases.check(principal, record.created_by, loaded, *ending)
    async with svc.lock:
        await svc.phases.cancel(record.id, "execute")
        tokens = svc.device_tokens(record)  # before they go with the devices
        record.state = "terminated"
        await svc.save(record)

    target = svc.phases.target(record, loaded, tokens) if loaded and ending else None

    async def remove() -> None:
        await remove_all(svc, principal, record.id, purge)
        if target is not None:
            target.device_tokens = {}  # gone with the devices: `clean` gets none

    async def finish() -> None:
        await svc.phases.remove_folder(record.id)
        await svc.release(record)

    if not svc.phases.ready or target is None:
        await remove()
        await finish()
    else:
        steps: list[Step] = ["terminate", remove] if "terminate" in ending else []
        if "terminate" not in ending:
            await remove()  # at once: the answer shows it done
        steps += ["clean"] if "clean" in ending else []
        svc.phases.in_turn(principal, target, steps, finish)
    return await svc.store.get_deployment(record.id) or record


async def remove_all(
    svc: DeploymentService, principal: Principal, deployment_id: int, purge: bool
) -> None:
    """Remove what a terminated deployment made, last made first (the twin too when
    `purge`); its device tokens go with its devices."""
    async with svc.lock:
        record = await svc.store.get_deployment(deployment_id)
        if record is None:
            return
        while record.journal and (purge or record.journal[-1]["type"] != "twin"):
            entry = record.journal[-1]
            await svc.parts.remove(principal, record.twin, entry["type"], entry["name"])
            record.journal.pop()
            await svc.save(record)
        record.secrets = None
        await svc.save(record)
