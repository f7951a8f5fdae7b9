"""Lifecycle runs (DTaaS) in PostgreSQL."""

from __future__ import annotations

import orjson

from twinlink.domain.runs import RunRecord
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.users import affected
from twinlink.store.runs import COLUMNS, run_of

_ACTIVE = "state IN ('queued', 'running')"


class RunTables:
    db: PostgresDatabase

    async def create_run(self, run: RunRecord) -> RunRecord:
        columns = COLUMNS.split(", ", 1)[1]  # all but the id, which the database gives
        async with self.db.transaction() as conn:
            run.id = await conn.fetchval(
                f"INSERT INTO runs ({columns}) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9,"
                " $10, $11, $12, $13, $14, $15, $16, $17, $18) RETURNING id",
                run.deployment_id, run.deployment, run.twin, run.phase, run.state,
                run.started_by, run.owner_id, run.created_ns, run.timeout_s, run.memory_mb,
                orjson.dumps(run.runner_tags).decode(), run.exit_code, run.started_ns,
                run.ended_ns, run.node, run.pid, run.error, run.token_id,
            )  # fmt: skip
        return run

    async def get_run(self, run_id: int) -> RunRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(f"SELECT {COLUMNS} FROM runs WHERE id = $1", run_id)
        return run_of(row) if row is not None else None

    async def list_runs(
        self,
        *,
        deployment_id: int | None = None,
        states: tuple[str, ...] = (),
        limit: int = 100,
        before_id: int | None = None,
    ) -> list[RunRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {COLUMNS} FROM runs WHERE ($1::bigint IS NULL OR deployment_id = $1)"
                " AND (cardinality($2::text[]) = 0 OR state = ANY($2::text[]))"
                " AND ($3::bigint IS NULL OR id < $3) ORDER BY id DESC LIMIT $4",
                deployment_id, list(states), before_id, limit,
            )  # fmt: skip
        return [run_of(r) for r in rows]

    async def claim_run(self, run_id: int, node: str) -> bool:
        return await self._changed(
            "UPDATE runs SET node = $1 WHERE id = $2 AND state = 'queued' AND node IS NULL",
            node, run_id,
        )  # fmt: skip

    async def set_run_token(self, run_id: int, token_id: int) -> None:
        await self._changed("UPDATE runs SET token_id = $1 WHERE id = $2", token_id, run_id)

    async def mark_run_running(self, run_id: int, pid: int, now_ns: int) -> bool:
        return await self._changed(
            "UPDATE runs SET state = 'running', pid = $1, started_ns = $2"
            " WHERE id = $3 AND state = 'queued'",
            pid, now_ns, run_id,
        )  # fmt: skip

    async def end_run(
        self, run_id: int, state: str, exit_code: int | None, error: str | None, now_ns: int
    ) -> bool:
        return await self._changed(
            "UPDATE runs SET state = $1, exit_code = $2, error = $3, ended_ns = $4"
            f" WHERE id = $5 AND {_ACTIVE}",
            state, exit_code, error, now_ns, run_id,
        )  # fmt: skip

    async def fail_interrupted_runs(
        self, node_like: str | None, error: str, now_ns: int
    ) -> list[RunRecord]:
        async with self.db.transaction() as conn:
            rows = await conn.fetch(
                f"SELECT {COLUMNS} FROM runs WHERE {_ACTIVE}"
                " AND node LIKE COALESCE($1::text, '%') ORDER BY id FOR UPDATE",
                node_like,
            )
            runs = [run_of(r) for r in rows]
            await conn.execute(
                "UPDATE runs SET state = 'failed', error = $1, ended_ns = $2"
                " WHERE id = ANY($3::bigint[])",
                error, now_ns, [run.id for run in runs],
            )  # fmt: skip
        return runs

    async def _changed(self, sql: str, *args: object) -> bool:
        async with self.db.transaction() as conn:
            return affected(await conn.execute(sql, *args)) > 0
