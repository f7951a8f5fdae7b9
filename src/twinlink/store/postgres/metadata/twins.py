"""Twins, their privacy parts, roles and relations in PostgreSQL."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import asyncpg
import orjson

from twinlink.domain.errors import ConflictError
from twinlink.domain.records import Edge, TwinRecord, TwinWrite, Visibility
from twinlink.store.postgres.db import Connection, PostgresDatabase
from twinlink.store.postgres.metadata.index import write_search_rows
from twinlink.store.postgres.metadata.sql import Args, like_escaped
from twinlink.store.postgres.metadata.visibility import part_visible
from twinlink.store.rows import EDGE_COLUMNS, edge_of, twin_of

_TWIN_COLUMNS = (
    "t.id, t.slug, t.dt_id, t.name, t.created_ns, t.modified_ns,"
    " ARRAY(SELECT p.privacy FROM twin_parts p WHERE p.twin_id = t.id) AS levels"
)
# Held by a transaction that writes relations: any number that is ours alone (db.py's
# migration lock is another).
_RELATIONS_LOCK = 0x7477_6C6E_6B00_0010


def _twin(row: asyncpg.Record) -> TwinRecord:
    # The parts' levels come as an array.
    return twin_of(row, sorted(row["levels"]))


class TwinTables:
    db: PostgresDatabase

    async def _twins(self, where: str, *args: Any) -> list[TwinRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(f"SELECT {_TWIN_COLUMNS} FROM twins t {where}", *args)
        return [_twin(r) for r in rows]

    async def get_twin(self, slug: str) -> TwinRecord | None:
        found = await self._twins("WHERE t.slug = $1", slug)
        return found[0] if found else None

    async def get_twin_by_dt_id(self, dt_id: str) -> TwinRecord | None:
        found = await self._twins("WHERE t.dt_id = $1", dt_id)
        return found[0] if found else None

    async def get_twins_by_dt_ids(self, dt_ids: Iterable[str]) -> dict[str, TwinRecord]:
        ids = list(dict.fromkeys(dt_ids))
        if not ids:
            return {}
        return {t.dt_id: t for t in await self._twins("WHERE t.dt_id = ANY($1::text[])", ids)}

    async def list_twins(
        self,
        vis: Visibility,
        *,
        limit: int,
        after_slug: str | None = None,
        keyword: str | None = None,
        name_contains: str | None = None,
        role_user_id: int | None = None,
    ) -> list[TwinRecord]:
        args = Args()
        where = part_visible(vis, "p.twin_id", "p.privacy", args)
        sql = [f"WHERE EXISTS (SELECT 1 FROM twin_parts p WHERE p.twin_id = t.id AND {where})"]
        if after_slug is not None:
            sql.append(f"AND t.slug > {args(after_slug)}")
        if name_contains:
            # SQLite's LIKE ignores the case of ASCII letters; ILIKE ignores all case.
            sql.append(f"AND t.name ILIKE {args(f'%{like_escaped(name_contains)}%')} ESCAPE '\\'")
        if role_user_id is not None:
            sql.append(
                "AND EXISTS (SELECT 1 FROM twin_roles r WHERE r.twin_id = t.id"
                f" AND r.user_id = {args(role_user_id)})"
            )
        if keyword:
            kw_where = part_visible(vis, "s.twin_id", "s.privacy", args)
            sql.append(
                "AND EXISTS (SELECT 1 FROM search_rows s JOIN search_keywords k ON k.row_id = s.id"
                f" WHERE s.twin_id = t.id AND lower(k.keyword) = lower({args(keyword)})"
                f" AND {kw_where})"
            )
        sql.append(f"ORDER BY t.slug LIMIT {args(limit)}")
        return await self._twins(" ".join(sql), *args)

    async def count_twins(self) -> int:
        async with self.db.connection() as conn:
            return int(await conn.fetchval("SELECT count(*) FROM twins"))

    async def twin_ids(self) -> set[int]:
        async with self.db.connection() as conn:
            rows = await conn.fetch("SELECT id FROM twins")
        return {int(r[0]) for r in rows}

    async def get_parts(self, twin_id: int) -> dict[str, dict[str, Any]]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "SELECT privacy, body FROM twin_parts WHERE twin_id = $1", twin_id
            )
        return {r["privacy"]: orjson.loads(r["body"]) for r in rows}

    async def save_twins(self, writes: list[TwinWrite]) -> list[TwinRecord]:
        """Write every twin in one transaction; refuse (and write nothing) if the relations
        would then hold a composition cycle."""
        if not writes:
            return []
        async with self.db.transaction() as conn:
            if any(w.edges for w in writes):
                # SQLite has one writer at a time; here two nodes could each add half of a
                # cycle, neither seeing the other's edge. Writers of relations queue here, so
                # each checks for cycles with every edge committed before it.
                await conn.execute("SELECT pg_advisory_xact_lock($1)", _RELATIONS_LOCK)
            ids = [await _save_one(conn, w) for w in writes]
            for w in writes:
                if await _in_cycle(conn, w.dt_id):
                    raise ConflictError(
                        f"the relations would make a composition cycle through {w.dt_id}: "
                        "a twin cannot be its own ancestor"
                    )
            rows = await conn.fetch(
                f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE t.id = ANY($1::bigint[])", ids
            )
        by_id = {r["id"]: _twin(r) for r in rows}
        return [by_id[i] for i in ids]

    async def delete_twins(self, twins: list[TwinRecord]) -> None:
        async with self.db.transaction() as conn:
            # Relations other twins declare stay: they name this id, which may come back.
            # The search index goes with the twin (ON DELETE CASCADE).
            await conn.execute(
                "DELETE FROM relations WHERE declared_by = ANY($1::text[])",
                [t.dt_id for t in twins],
            )
            await conn.execute(
                "DELETE FROM twins WHERE id = ANY($1::bigint[])", [t.id for t in twins]
            )

    async def edges_touching(self, dt_ids: Iterable[str]) -> list[Edge]:
        ids = list(dict.fromkeys(dt_ids))
        if not ids:
            return []
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {EDGE_COLUMNS} FROM relations WHERE source = ANY($1::text[])"
                f" UNION SELECT {EDGE_COLUMNS} FROM relations WHERE target = ANY($1::text[])"
                " ORDER BY source, kind, target, declared_by",
                ids,
            )
        return [edge_of(r) for r in rows]

    async def descendants(self, roots: Iterable[str], exclude: str) -> set[str]:
        """Every twin reachable from `roots` along parent->child edges not touching `exclude`."""
        start = list(dict.fromkeys(roots))
        if not start:
            return set()
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "WITH RECURSIVE d(id) AS (SELECT unnest($1::text[]) COLLATE \"C\""
                " UNION SELECT r.target FROM relations r JOIN d ON r.source = d.id"
                " WHERE r.kind = 'parent' AND r.source <> $2 AND r.target <> $2)"
                " SELECT id FROM d",
                start, exclude,
            )  # fmt: skip
        return {r[0] for r in rows}

    async def get_role(self, twin_id: int, user_id: int) -> str | None:
        async with self.db.connection() as conn:
            role = await conn.fetchval(
                "SELECT role FROM twin_roles WHERE twin_id = $1 AND user_id = $2", twin_id, user_id
            )
        return None if role is None else str(role)

    async def list_roles(self, twin_id: int) -> list[tuple[int, str, str]]:
        async with self.db.connection() as conn:
            # SQLite orders the NOCASE user names without case (ASCII letters).
            rows = await conn.fetch(
                "SELECT r.user_id, u.username, r.role FROM twin_roles r JOIN users u"
                " ON u.id = r.user_id WHERE r.twin_id = $1"
                ' ORDER BY lower(u.username) COLLATE "C", u.username COLLATE "C"',
                twin_id,
            )
        return [(r[0], r[1], r[2]) for r in rows]

    async def set_role(self, twin_id: int, user_id: int, role: str | None) -> None:
        async with self.db.transaction() as conn:
            if role is None:
                await conn.execute(
                    "DELETE FROM twin_roles WHERE twin_id = $1 AND user_id = $2", twin_id, user_id
                )
            else:
                await conn.execute(
                    "INSERT INTO twin_roles (twin_id, user_id, role) VALUES ($1, $2, $3)"
                    " ON CONFLICT (twin_id, user_id) DO UPDATE SET role = excluded.role",
                    twin_id, user_id, role,
                )  # fmt: skip


async def _save_one(conn: Connection, w: TwinWrite) -> int:
    if w.twin_id is None:
        twin_id = await conn.fetchval(
            "INSERT INTO twins (slug, dt_id, name, created_ns, modified_ns)"
            " VALUES ($1, $2, $3, $4, $5) RETURNING id",
            w.slug, w.dt_id, w.name, w.created_ns, w.modified_ns,
        )  # fmt: skip
        if w.owner_user_id is not None:
            await conn.execute(
                "INSERT INTO twin_roles (twin_id, user_id, role) VALUES ($1, $2, 'owner')",
                twin_id, w.owner_user_id,
            )  # fmt: skip
    else:
        twin_id = w.twin_id
        await conn.execute(
            "UPDATE twins SET slug = $1, dt_id = $2, name = $3, modified_ns = $4 WHERE id = $5",
            w.slug, w.dt_id, w.name, w.modified_ns, twin_id,
        )  # fmt: skip
    await conn.execute("DELETE FROM twin_parts WHERE twin_id = $1", twin_id)
    await conn.executemany(
        "INSERT INTO twin_parts (twin_id, privacy, body) VALUES ($1, $2, $3)",
        [(twin_id, level, orjson.dumps(body).decode()) for level, body in w.parts.items()],
    )
    await conn.execute("DELETE FROM relations WHERE declared_by = $1", w.dt_id)
    await conn.executemany(
        f"INSERT INTO relations ({EDGE_COLUMNS}) VALUES ($1, $2, $3, $4, $5)"
        " ON CONFLICT (source, kind, target, declared_by) DO UPDATE SET privacy = excluded.privacy",
        [(e.source, e.kind, e.target, e.declared_by, e.privacy) for e in w.edges],
    )
    await write_search_rows(conn, twin_id, w.search_rows)
    return int(twin_id)


async def _in_cycle(conn: Connection, dt_id: str) -> bool:
    """True when `dt_id` can reach itself along parent->child edges (UNION stops on revisits)."""
    found = await conn.fetchval(
        "WITH RECURSIVE d(id) AS ("
        " SELECT target FROM relations WHERE source = $1 AND kind = 'parent'"
        " UNION SELECT r.target FROM relations r JOIN d ON r.source = d.id WHERE r.kind = 'parent')"
        " SELECT 1 FROM d WHERE id = $1 LIMIT 1",
        dt_id,
    )
    return found is not None
