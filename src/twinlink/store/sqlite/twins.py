"""Twins, their privacy parts, roles and relations in SQLite."""

from __future__ import annotations

import sqlite3
from collections.abc import Iterable
from typing import Any

import orjson

from twinlink.domain.errors import ConflictError
from twinlink.domain.records import Edge, TwinRecord, TwinWrite, Visibility
from twinlink.store.rows import EDGE_COLUMNS, edge_of, twin_of
from twinlink.store.sqlite.db import Database, next_id
from twinlink.store.sqlite.search import delete_search_rows, write_search_rows
from twinlink.store.sqlite.visibility import part_visible

_TWIN_COLUMNS = (
    "t.id, t.slug, t.dt_id, t.name, t.created_ns, t.modified_ns,"
    " (SELECT group_concat(p.privacy, char(31)) FROM twin_parts p WHERE p.twin_id = t.id) AS levels"
)


def _twin(row: sqlite3.Row) -> TwinRecord:
    # The parts' levels come as one string, joined by char(31) (group_concat).
    return twin_of(row, sorted(row["levels"].split("\x1f")) if row["levels"] else [])


class TwinTables:
    db: Database

    async def get_twin(self, slug: str) -> TwinRecord | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE t.slug = ?", (slug,)
            ).fetchone()
        )
        return _twin(row) if row else None

    async def get_twin_by_dt_id(self, dt_id: str) -> TwinRecord | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE t.dt_id = ?", (dt_id,)
            ).fetchone()
        )
        return _twin(row) if row else None

    async def get_twins_by_dt_ids(self, dt_ids: Iterable[str]) -> dict[str, TwinRecord]:
        ids = list(dict.fromkeys(dt_ids))
        if not ids:
            return {}

        def _get(c: sqlite3.Connection) -> list[sqlite3.Row]:
            marks = ", ".join("?" * len(ids))
            return c.execute(
                f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE t.dt_id IN ({marks})", ids
            ).fetchall()

        return {r["dt_id"]: _twin(r) for r in await self.db.read(_get)}

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
        where, args = part_visible(vis, "p.twin_id", "p.privacy")
        sql = [
            f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE EXISTS"
            f" (SELECT 1 FROM twin_parts p WHERE p.twin_id = t.id AND {where})"
        ]
        if after_slug is not None:
            sql.append("AND t.slug > ?")
            args.append(after_slug)
        if name_contains:
            sql.append("AND t.name LIKE ? ESCAPE '\\'")
            escaped = name_contains.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")
            args.append(f"%{escaped}%")
        if role_user_id is not None:
            sql.append(
                "AND EXISTS (SELECT 1 FROM twin_roles r WHERE r.twin_id = t.id AND r.user_id = ?)"
            )
            args.append(role_user_id)
        if keyword:
            kw_where, kw_args = part_visible(vis, "s.twin_id", "s.privacy")
            sql.append(
                "AND EXISTS (SELECT 1 FROM search_rows s JOIN search_keywords k ON k.row_id = s.id"
                f" WHERE s.twin_id = t.id AND k.keyword = ? AND {kw_where})"
            )
            args.extend([keyword, *kw_args])
        sql.append("ORDER BY t.slug LIMIT ?")
        args.append(limit)
        query = " ".join(sql)
        return [_twin(r) for r in await self.db.read(lambda c: c.execute(query, args).fetchall())]

    async def count_twins(self) -> int:
        return await self.db.read(lambda c: c.execute("SELECT count(*) FROM twins").fetchone()[0])

    async def twin_ids(self) -> set[int]:
        rows = await self.db.read(lambda c: c.execute("SELECT id FROM twins").fetchall())
        return {int(r[0]) for r in rows}

    async def get_parts(self, twin_id: int) -> dict[str, dict[str, Any]]:
        rows = await self.db.read(
            lambda c: c.execute(
                "SELECT privacy, body FROM twin_parts WHERE twin_id = ?", (twin_id,)
            ).fetchall()
        )
        return {r["privacy"]: orjson.loads(r["body"]) for r in rows}

    async def save_twins(self, writes: list[TwinWrite]) -> list[TwinRecord]:
        """Write every twin in one transaction; refuse (and write nothing) if the relations
        would then hold a composition cycle."""
        if not writes:
            return []

        def _save(c: sqlite3.Connection) -> list[TwinRecord]:
            ids = [_save_one(c, w) for w in writes]
            for w in writes:
                if _in_cycle(c, w.dt_id):
                    raise ConflictError(
                        f"the relations would make a composition cycle through {w.dt_id}: "
                        "a twin cannot be its own ancestor"
                    )
            return [
                _twin(
                    c.execute(
                        f"SELECT {_TWIN_COLUMNS} FROM twins t WHERE t.id = ?", (i,)
                    ).fetchone()
                )
                for i in ids
            ]

        return await self.db.write(_save)

    async def delete_twins(self, twins: list[TwinRecord]) -> None:
        def _delete(c: sqlite3.Connection) -> None:
            for t in twins:
                delete_search_rows(c, t.id)
                # Relations other twins declare stay: they name this id, which may come back.
                c.execute("DELETE FROM relations WHERE declared_by = ?", (t.dt_id,))
                c.execute("DELETE FROM twins WHERE id = ?", (t.id,))

        await self.db.write(_delete)

    async def edges_touching(self, dt_ids: Iterable[str]) -> list[Edge]:
        ids = list(dict.fromkeys(dt_ids))
        if not ids:
            return []

        def _edges(c: sqlite3.Connection) -> list[sqlite3.Row]:
            marks = ", ".join("?" * len(ids))
            return c.execute(
                f"SELECT {EDGE_COLUMNS} FROM relations WHERE source IN ({marks})"
                f" UNION SELECT {EDGE_COLUMNS} FROM relations WHERE target IN ({marks})",
                ids + ids,
            ).fetchall()

        return [edge_of(r) for r in await self.db.read(_edges)]

    async def descendants(self, roots: Iterable[str], exclude: str) -> set[str]:
        """Every twin reachable from `roots` along parent->child edges not touching `exclude`."""
        start = list(dict.fromkeys(roots))
        if not start:
            return set()

        def _walk(c: sqlite3.Connection) -> set[str]:
            marks = ", ".join("(?)" * 1 for _ in start)
            rows = c.execute(
                f"WITH RECURSIVE d(id) AS (VALUES {marks}"
                " UNION SELECT r.target FROM relations r JOIN d ON r.source = d.id"
                " WHERE r.kind = 'parent' AND r.source <> ? AND r.target <> ?)"
                " SELECT id FROM d",
                (*start, exclude, exclude),
            ).fetchall()
            return {r[0] for r in rows}

        return await self.db.read(_walk)

    async def get_role(self, twin_id: int, user_id: int) -> str | None:
        row = await self.db.read(
            lambda c: c.execute(
                "SELECT role FROM twin_roles WHERE twin_id = ? AND user_id = ?", (twin_id, user_id)
            ).fetchone()
        )
        return row[0] if row else None

    async def list_roles(self, twin_id: int) -> list[tuple[int, str, str]]:
        rows = await self.db.read(
            lambda c: c.execute(
                "SELECT r.user_id, u.username, r.role FROM twin_roles r JOIN users u"
                " ON u.id = r.user_id WHERE r.twin_id = ? ORDER BY u.username",
                (twin_id,),
            ).fetchall()
        )
        return [(r[0], r[1], r[2]) for r in rows]

    async def set_role(self, twin_id: int, user_id: int, role: str | None) -> None:
        def _set(c: sqlite3.Connection) -> None:
            if role is None:
                c.execute(
                    "DELETE FROM twin_roles WHERE twin_id = ? AND user_id = ?", (twin_id, user_id)
                )
            else:
                c.execute(
                    "INSERT INTO twin_roles(twin_id, user_id, role) VALUES (?, ?, ?)"
                    " ON CONFLICT(twin_id, user_id) DO UPDATE SET role = excluded.role",
                    (twin_id, user_id, role),
                )

        await self.db.write(_set)


def _save_one(c: sqlite3.Connection, w: TwinWrite) -> int:
    if w.twin_id is None:
        twin_id = next_id(c, "twins")
        c.execute(
            "INSERT INTO twins(id, slug, dt_id, name, created_ns, modified_ns)"
            " VALUES (?, ?, ?, ?, ?, ?)",
            (twin_id, w.slug, w.dt_id, w.name, w.created_ns, w.modified_ns),
        )
        if w.owner_user_id is not None:
            c.execute(
                "INSERT INTO twin_roles(twin_id, user_id, role) VALUES (?, ?, 'owner')",
                (twin_id, w.owner_user_id),
            )
    else:
        twin_id = w.twin_id
        c.execute(
            "UPDATE twins SET slug = ?, dt_id = ?, name = ?, modified_ns = ? WHERE id = ?",
            (w.slug, w.dt_id, w.name, w.modified_ns, twin_id),
        )
    c.execute("DELETE FROM twin_parts WHERE twin_id = ?", (twin_id,))
    c.executemany(
        "INSERT INTO twin_parts(twin_id, privacy, body) VALUES (?, ?, ?)",
        [(twin_id, level, orjson.dumps(body).decode()) for level, body in w.parts.items()],
    )
    c.execute("DELETE FROM relations WHERE declared_by = ?", (w.dt_id,))
    c.executemany(
        "INSERT OR REPLACE INTO relations(source, kind, target, declared_by, privacy)"
        " VALUES (?, ?, ?, ?, ?)",
        [(e.source, e.kind, e.target, e.declared_by, e.privacy) for e in w.edges],
    )
    write_search_rows(c, twin_id, w.search_rows)
    return twin_id


def _in_cycle(c: sqlite3.Connection, dt_id: str) -> bool:
    """True when `dt_id` can reach itself along parent->child edges (UNION stops on revisits)."""
    row = c.execute(
        "WITH RECURSIVE d(id) AS ("
        " SELECT target FROM relations WHERE source = ? AND kind = 'parent'"
        " UNION SELECT r.target FROM relations r JOIN d ON r.source = d.id WHERE r.kind = 'parent')"
        " SELECT 1 FROM d WHERE id = ? LIMIT 1",
        (dt_id, dt_id),
    ).fetchone()
    return row is not None
