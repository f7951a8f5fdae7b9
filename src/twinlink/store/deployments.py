"""The interface deployment stores implement (MetadataStore inherits it)."""

from __future__ import annotations

from typing import Any, Protocol

import orjson

from twinlink.domain.deployments import DeploymentRecord

# The columns every backend reads, in the order `deployment_of` takes them.
COLUMNS = (
    "id, name, package, package_ref, parameters, state, twin, journal, secrets, created_by,"
    " created_ns, updated_ns, error"
)


def deployment_of(row: Any) -> DeploymentRecord:
    """A deployment from a row of COLUMNS (SQLite's or PostgreSQL's)."""
    return DeploymentRecord(
        id=row[0],
        name=row[1],
        package=row[2],
        package_ref=row[3],
        parameters=orjson.loads(row[4]),
        state=row[5],
        twin=row[6],
        journal=orjson.loads(row[7]),
        secrets=bytes(row[8]) if row[8] is not None else None,
        created_by=row[9],
        created_ns=row[10],
        updated_ns=row[11],
        error=row[12],
    )


class DeploymentStore(Protocol):
    async def create_deployment(self, record: DeploymentRecord) -> DeploymentRecord:
        """Store a new deployment (its `id` is assigned); ConflictError when a live deployment
        (not terminated or failed) has its name."""
        ...

    async def save_deployment(self, record: DeploymentRecord) -> None:
        """Write the record's changing fields: package, parameters, state, journal, secrets,
        error, updated_ns."""
        ...

    async def get_deployment(self, deployment_id: int) -> DeploymentRecord | None: ...

    async def find_deployment(self, name: str) -> DeploymentRecord | None:
        """The live deployment of that name, else the newest ended one, else None."""
        ...

    async def list_deployments(self, state: str | None = None) -> list[DeploymentRecord]:
        """Newest first; of one state when `state` is given."""
        ...
