"""Deployments (DTaaS) in PostgreSQL."""

from __future__ import annotations

import orjson

from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.store.deployments import COLUMNS as _COLUMNS
from twinlink.store.deployments import deployment_of
from twinlink.store.postgres.db import PostgresDatabase


class DeploymentTables:
    db: PostgresDatabase

    async def create_deployment(self, record: DeploymentRecord) -> DeploymentRecord:
        try:
            async with self.db.transaction() as conn:
                record.id = await conn.fetchval(
                    "INSERT INTO deployments (name, package, package_ref, parameters, state,"
                    " twin, journal, secrets, created_by, created_ns, updated_ns, error)"
                    " VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12) RETURNING id",
                    record.name, record.package, record.package_ref,
                    orjson.dumps(record.parameters).decode(), record.state, record.twin,
                    orjson.dumps(record.journal).decode(), record.secrets, record.created_by,
                    record.created_ns, record.updated_ns, record.error,
                )  # fmt: skip
        except WriteConflictError as err:
            raise ConflictError(f"a deployment named {record.name!r} exists already") from err
        return record

    async def save_deployment(self, record: DeploymentRecord) -> None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE deployments SET package = $1, package_ref = $2, parameters = $3,"
                " state = $4, journal = $5, secrets = $6, error = $7, updated_ns = $8"
                " WHERE id = $9",
                record.package, record.package_ref, orjson.dumps(record.parameters).decode(),
                record.state, orjson.dumps(record.journal).decode(), record.secrets,
                record.error, record.updated_ns, record.id,
            )  # fmt: skip

    async def get_deployment(self, deployment_id: int) -> DeploymentRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(
                f"SELECT {_COLUMNS} FROM deployments WHERE id = $1", deployment_id
            )
        return deployment_of(row) if row is not None else None

    async def find_deployment(self, name: str) -> DeploymentRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(
                f"SELECT {_COLUMNS} FROM deployments WHERE name = $1"
                " ORDER BY state IN ('terminated', 'failed'), id DESC LIMIT 1",
                name,
            )
        return deployment_of(row) if row is not None else None

    async def list_deployments(self, state: str | None = None) -> list[DeploymentRecord]:
        where, args = ("WHERE state = $1", [state]) if state is not None else ("", [])
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {_COLUMNS} FROM deployments {where} ORDER BY id DESC", *args
            )
        return [deployment_of(r) for r in rows]
