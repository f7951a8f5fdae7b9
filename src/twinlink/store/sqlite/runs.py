"""Lifecycle runs (DTaaS) in SQLite."""

from __future__ import annotations

import sqlite3

import orjson

from twinlink.domain.runs import RunRecord
from twinlink.store.runs import ACTIVE, COLUMNS, run_of
from twinlink.store.sqlite.db import Database, next_id

_ACTIVE = "state IN ('queued', 'running')"
assert ACTIVE == ("queued", "running")


class RunTables:
    db: Database

    async def create_run(self, run: RunRecord) -> RunRecord:
        def _create(c: sqlite3.Connection) -> int:
            rid = next_id(c, "runs")
            c.execute(
                f"INSERT INTO runs({COLUMNS}) VALUES"
                " (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (rid, run.deployment_id, run.deployment, run.twin, run.phase, run.state,
                 run.started_by, run.owner_id, run.created_ns, run.timeout_s, run.memory_mb,
                 orjson.dumps(run.runner_tags).decode(), run.exit_code, run.started_ns,
                 run.ended_ns, run.node, run.pid, run.error, run.token_id),
            )  # fmt: skip
            return rid

        run.id = await self.db.write(_create)
        return run

    async def get_run(self, run_id: int) -> RunRecord | None:
        row = await self.db.read(
            lambda c: c.execute(f"SELECT {COLUMNS} FROM runs WHERE id = ?", (run_id,)).fetchone()
        )
        return run_of(row) if row is not None else None

    async def list_runs(
        self,
        *,
        deployment_id: int | None = None,
        states: tuple[str, ...] = (),
        limit: int = 100,
        before_id: int | None = None,
    ) -> list[RunRecord]:
        where: list[str] = ["1"]
        args: list[object] = []
        if deployment_id is not None:
            where.append("deployment_id = ?")
            args.append(deployment_id)
        if states:
            where.append(f"state IN ({', '.join('?' * len(states))})")
            args.extend(states)
        if before_id is not None:
            where.append("id < ?")
            args.append(before_id)
        sql = f"SELECT {COLUMNS} FROM runs WHERE {' AND '.join(where)} ORDER BY id DESC LIMIT ?"
        rows = await self.db.read(lambda c: c.execute(sql, (*args, limit)).fetchall())
        return [run_of(r) for r in rows]

    async def claim_run(self, run_id: int, node: str) -> bool:
        return await self._changed(
            "UPDATE runs SET node = ? WHERE id = ? AND state = 'queued' AND node IS NULL",
            (node, run_id),
        )

    async def set_run_token(self, run_id: int, token_id: int) -> None:
        await self._changed("UPDATE runs SET token_id = ? WHERE id = ?", (token_id, run_id))

    async def mark_run_running(self, run_id: int, pid: int, now_ns: int) -> bool:
        return await self._changed(
            "UPDATE runs SET state = 'running', pid = ?, started_ns = ?"
            " WHERE id = ? AND state = 'queued'",
            (pid, now_ns, run_id),
        )

    async def end_run(
        self, run_id: int, state: str, exit_code: int | None, error: str | None, now_ns: int
    ) -> bool:
        return await self._changed(
            "UPDATE runs SET state = ?, exit_code = ?, error = ?, ended_ns = ?"
            f" WHERE id = ? AND {_ACTIVE}",
            (state, exit_code, error, now_ns, run_id),
        )

    async def fail_interrupted_runs(
        self, node_like: str | None, error: str, now_ns: int
    ) -> list[RunRecord]:
        mine = " AND node IS NOT NULL" if node_like is None else " AND node LIKE ?"
        args = () if node_like is None else (node_like,)

        def _fail(c: sqlite3.Connection) -> list[RunRecord]:
            rows = c.execute(f"SELECT {COLUMNS} FROM runs WHERE {_ACTIVE}{mine}", args)
            runs = [run_of(r) for r in rows.fetchall()]
            c.executemany(
                "UPDATE runs SET state = 'failed', error = ?, ended_ns = ? WHERE id = ?",
                [(error, now_ns, run.id) for run in runs],
            )
            return runs

        return await self.db.write(_fail)

    async def _changed(self, sql: str, args: tuple[object, ...]) -> bool:
        return bool(await self.db.write(lambda c: c.execute(sql, args).rowcount > 0))
