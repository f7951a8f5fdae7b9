"""Deployments (DTaaS) in SQLite."""

from __future__ import annotations

import sqlite3

import orjson

from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.store.deployments import COLUMNS as _COLUMNS
from twinlink.store.deployments import deployment_of
from twinlink.store.sqlite.db import Database, next_id


class DeploymentTables:
    db: Database

    async def create_deployment(self, record: DeploymentRecord) -> DeploymentRecord:
        def _create(c: sqlite3.Connection) -> int:
            did = next_id(c, "deployments")
            c.execute(
                f"INSERT INTO deployments({_COLUMNS})"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (did, record.name, record.package, record.package_ref,
                 orjson.dumps(record.parameters), record.state, record.twin,
                 orjson.dumps(record.journal), record.secrets, record.created_by,
                 record.created_ns, record.updated_ns, record.error),
            )  # fmt: skip
            return did

        try:
            record.id = await self.db.write(_create)
        except WriteConflictError as err:
            raise ConflictError(f"a deployment named {record.name!r} exists already") from err
        return record

    async def save_deployment(self, record: DeploymentRecord) -> None:
        def _save(c: sqlite3.Connection) -> None:
            c.execute(
                "UPDATE deployments SET package = ?, package_ref = ?, parameters = ?, state = ?,"
                " journal = ?, secrets = ?, error = ?, updated_ns = ? WHERE id = ?",
                (record.package, record.package_ref, orjson.dumps(record.parameters),
                 record.state, orjson.dumps(record.journal), record.secrets, record.error,
                 record.updated_ns, record.id),
            )  # fmt: skip

        await self.db.write(_save)

    async def get_deployment(self, deployment_id: int) -> DeploymentRecord | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {_COLUMNS} FROM deployments WHERE id = ?", (deployment_id,)
            ).fetchone()
        )
        return deployment_of(row) if row is not None else None

    async def find_deployment(self, name: str) -> DeploymentRecord | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {_COLUMNS} FROM deployments WHERE name = ?"
                " ORDER BY state IN ('terminated', 'failed'), id DESC LIMIT 1",
                (name,),
            ).fetchone()
        )
        return deployment_of(row) if row is not None else None

    async def list_deployments(self, state: str | None = None) -> list[DeploymentRecord]:
        where, args = ("WHERE state = ?", (state,)) if state is not None else ("", ())
        return await self.db.read(
            lambda c: [
                deployment_of(row)
                for row in c.execute(
                    f"SELECT {_COLUMNS} FROM deployments {where} ORDER BY id DESC", args
                )
            ]
        )
