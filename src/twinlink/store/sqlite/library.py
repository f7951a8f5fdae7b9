"""The library's assets, versions, tags and holds in SQLite (migration 0008)."""

from __future__ import annotations

import sqlite3
from collections.abc import AsyncIterator, Iterable
from contextlib import asynccontextmanager

import orjson

from twinlink.domain.library import AssetRecord, VersionRecord
from twinlink.store.library import (
    ASSET_COLUMNS,
    VERSION_COLUMNS,
    AssetFields,
    asset_of,
    files_json,
    version_of,
)
from twinlink.store.sqlite.db import Database, next_id

# SQLite's LIKE escapes: a search for "50%" or "a_b" means those characters.
_LIKE_ESCAPE = str.maketrans({"%": r"\%", "_": r"\_", "\\": r"\\"})


class LibraryTables:
    db: Database

    async def get_asset(self, scope: str, kind: str, name: str) -> AssetRecord | None:
        def _get(c: sqlite3.Connection) -> AssetRecord | None:
            row = c.execute(
                f"SELECT {ASSET_COLUMNS} FROM library_assets"
                " WHERE scope = ? AND kind = ? AND name = ?",
                (scope, kind, name),
            ).fetchone()
            return _with_tags(c, [asset_of(row)])[0] if row else None

        return await self.db.read(_get)

    async def list_assets(
        self,
        scopes: list[str] | None,
        *,
        kind: str | None,
        text: str | None,
        limit: int,
        after: tuple[str, str, str] | None,
    ) -> list[AssetRecord]:
        where: list[str] = []
        args: list[object] = []
        if scopes is not None:
            where.append(f"scope IN ({', '.join('?' * len(scopes)) or 'NULL'})")
            args += scopes
        if kind is not None:
            where.append("kind = ?")
            args.append(kind)
        if text:
            like = f"%{text.lower().translate(_LIKE_ESCAPE)}%"
            where.append(
                "(lower(name) LIKE ? ESCAPE '\\' OR lower(description) LIKE ? ESCAPE '\\'"
                " OR lower(keywords) LIKE ? ESCAPE '\\')"
            )
            args += [like, like, like]
        if after is not None:
            where.append("(scope, kind, name) > (?, ?, ?)")
            args += after
        sql = f"SELECT {ASSET_COLUMNS} FROM library_assets"
        sql += f" WHERE {' AND '.join(where)}" if where else ""
        sql += " ORDER BY scope, kind, name LIMIT ?"
        args.append(limit)

        def _list(c: sqlite3.Connection) -> list[AssetRecord]:
            return _with_tags(c, [asset_of(r) for r in c.execute(sql, args)])

        return await self.db.read(_list)

    async def search_assets(
        self,
        scopes: list[str] | None,
        terms: list[str],
        *,
        keyword: str | None,
        limit: int,
        offset: int,
    ) -> tuple[list[AssetRecord], int]:
        where: list[str] = []
        args: list[object] = []
        in_name: list[str] = []
        name_args: list[object] = []
        if scopes is not None:
            where.append(f"scope IN ({', '.join('?' * len(scopes)) or 'NULL'})")
            args += scopes
        for term in terms:
            like = f"%{term.translate(_LIKE_ESCAPE)}%"
            where.append(
                "(lower(name) LIKE ? ESCAPE '\\' OR lower(description) LIKE ? ESCAPE '\\'"
                " OR lower(keywords) LIKE ? ESCAPE '\\')"
            )
            args += [like, like, like]
            in_name.append("lower(name) LIKE ? ESCAPE '\\'")
            name_args.append(like)
        if keyword:
            where.append("EXISTS (SELECT 1 FROM json_each(keywords) WHERE value = ?)")
            args.append(keyword)
        cond = f" WHERE {' AND '.join(where)}" if where else ""
        first = f"CASE WHEN {' AND '.join(in_name)} THEN 0 ELSE 1 END, " if in_name else ""

        def _search(c: sqlite3.Connection) -> tuple[list[AssetRecord], int]:
            total = c.execute(f"SELECT count(*) FROM library_assets{cond}", args).fetchone()[0]
            rows = c.execute(
                f"SELECT {ASSET_COLUMNS} FROM library_assets{cond}"
                f" ORDER BY {first}scope, kind, name LIMIT ? OFFSET ?",
                [*args, *name_args, limit, offset],
            )
            return _with_tags(c, [asset_of(r) for r in rows]), total

        return await self.db.read(_search)

    async def put_version(
        self,
        scope: str,
        kind: str,
        name: str,
        version: VersionRecord,
        tags: Iterable[str],
        fields: AssetFields,
        now_ns: int,
    ) -> tuple[AssetRecord, VersionRecord, bool]:
        tags = list(tags)

        def _put(c: sqlite3.Connection) -> tuple[AssetRecord, VersionRecord, bool]:
            row = c.execute(
                "SELECT id FROM library_assets WHERE scope = ? AND kind = ? AND name = ?",
                (scope, kind, name),
            ).fetchone()
            if row is None:
                asset_id = next_id(c, "library_assets")
                c.execute(
                    "INSERT INTO library_assets(id, scope, kind, name, created_by, created_ns,"
                    " updated_ns) VALUES (?, ?, ?, ?, ?, ?, ?)",
                    (asset_id, scope, kind, name, version.created_by, now_ns, now_ns),
                )
            else:
                asset_id = row[0]
            created = (
                c.execute(
                    "INSERT INTO library_versions(asset_id, digest, files, size, meta,"
                    " created_by, created_ns) VALUES (?, ?, ?, ?, ?, ?, ?)"
                    " ON CONFLICT (asset_id, digest) DO NOTHING",
                    (asset_id, version.digest, files_json(version.files), version.size,
                     orjson.dumps(version.meta).decode(), version.created_by, now_ns),
                ).rowcount
                == 1
            )  # fmt: skip
            for tag in tags:
                _set_tag(c, asset_id, tag, version.digest, now_ns)
            _update(c, asset_id, fields, now_ns)
            stored = c.execute(
                f"SELECT {VERSION_COLUMNS} FROM library_versions WHERE asset_id = ? AND digest = ?",
                (asset_id, version.digest),
            ).fetchone()
            return _asset_by_id(c, asset_id), version_of(stored), created

        return await self.db.write(_put)

    async def update_asset(
        self, asset_id: int, fields: AssetFields, now_ns: int
    ) -> AssetRecord | None:
        def _patch(c: sqlite3.Connection) -> AssetRecord | None:
            if c.execute("SELECT 1 FROM library_assets WHERE id = ?", (asset_id,)).fetchone():
                _update(c, asset_id, fields, now_ns)
                return _asset_by_id(c, asset_id)
            return None

        return await self.db.write(_patch)

    async def delete_asset(self, asset_id: int) -> list[str] | None:
        def _delete(c: sqlite3.Connection) -> list[str] | None:
            holders = _holders(c, asset_id, None)
            if holders:
                return holders
            c.execute("DELETE FROM library_assets WHERE id = ?", (asset_id,))
            return None

        return await self.db.write(_delete)

    async def list_versions(self, asset_id: int) -> list[VersionRecord]:
        return await self.db.read(
            lambda c: [
                version_of(r)
                for r in c.execute(
                    f"SELECT {VERSION_COLUMNS} FROM library_versions WHERE asset_id = ?"
                    " ORDER BY created_ns DESC, digest",
                    (asset_id,),
                )
            ]
        )

    async def get_version(self, asset_id: int, digest: str) -> VersionRecord | None:
        def _get(c: sqlite3.Connection) -> VersionRecord | None:
            row = c.execute(
                f"SELECT {VERSION_COLUMNS} FROM library_versions WHERE asset_id = ? AND digest = ?",
                (asset_id, digest),
            ).fetchone()
            return version_of(row) if row else None

        return await self.db.read(_get)

    async def find_digests(self, asset_id: int, prefix: str) -> list[str]:
        # Digests are lower-case hex after "sha256:", so a range scan finds the prefix.
        return await self.db.read(
            lambda c: [
                r[0]
                for r in c.execute(
                    "SELECT digest FROM library_versions WHERE asset_id = ? AND digest >= ?"
                    " AND digest < ? ORDER BY digest LIMIT 5",
                    (asset_id, prefix, prefix + "~"),
                )
            ]
        )

    async def delete_version(self, asset_id: int, digest: str) -> list[str] | None:
        def _delete(c: sqlite3.Connection) -> list[str] | None:
            holders = _holders(c, asset_id, digest)
            if holders:
                return holders
            c.execute(
                "DELETE FROM library_versions WHERE asset_id = ? AND digest = ?",
                (asset_id, digest),
            )  # its tags go with it (ON DELETE CASCADE)
            return None

        return await self.db.write(_delete)

    async def set_tag(self, asset_id: int, tag: str, digest: str, now_ns: int) -> None:
        await self.db.write(lambda c: _set_tag(c, asset_id, tag, digest, now_ns))

    async def delete_tag(self, asset_id: int, tag: str) -> bool:
        return await self.db.write(
            lambda c: (
                c.execute(
                    "DELETE FROM library_tags WHERE asset_id = ? AND tag = ?", (asset_id, tag)
                ).rowcount
                > 0
            )
        )

    async def add_holds(self, holder: str, versions: Iterable[tuple[int, str]]) -> None:
        rows = [(asset_id, digest, holder) for asset_id, digest in versions]
        await self.db.write(
            lambda c: c.executemany(
                "INSERT INTO library_holds(asset_id, digest, holder) VALUES (?, ?, ?)"
                " ON CONFLICT DO NOTHING",
                rows,
            )
        )

    async def release_holds(self, holder: str) -> int:
        return await self.db.write(
            lambda c: c.execute("DELETE FROM library_holds WHERE holder = ?", (holder,)).rowcount
        )

    async def list_holders(self, asset_id: int, digest: str | None = None) -> list[str]:
        return await self.db.read(lambda c: _holders(c, asset_id, digest))

    async def referenced_blobs(self, sha256s: Iterable[str]) -> set[str]:
        wanted = sorted(set(sha256s))
        if not wanted:
            return set()
        marks = ", ".join("?" * len(wanted))
        return await self.db.read(
            lambda c: {
                r[0]
                for r in c.execute(
                    "SELECT DISTINCT json_extract(f.value, '$.sha256') AS sha256"
                    " FROM library_versions v, json_each(v.files) f"
                    f" WHERE json_extract(f.value, '$.sha256') IN ({marks})",
                    wanted,
                )
            }
        )

    @asynccontextmanager
    async def blob_lock(self) -> AsyncIterator[None]:
        # One process has the SQLite file (workers share PostgreSQL): the service's own
        # lock is enough.
        yield


def _set_tag(c: sqlite3.Connection, asset_id: int, tag: str, digest: str, now_ns: int) -> None:
    c.execute(
        "INSERT INTO library_tags(asset_id, tag, digest, updated_ns) VALUES (?, ?, ?, ?)"
        " ON CONFLICT (asset_id, tag) DO UPDATE SET digest = excluded.digest,"
        " updated_ns = excluded.updated_ns",
        (asset_id, tag, digest, now_ns),
    )
    c.execute("UPDATE library_assets SET updated_ns = ? WHERE id = ?", (now_ns, asset_id))


def _update(c: sqlite3.Connection, asset_id: int, fields: AssetFields, now_ns: int) -> None:
    changes = fields.as_dict()
    if "keywords" in changes:
        changes["keywords"] = orjson.dumps(changes["keywords"]).decode()
    sets = "".join(f", {column} = ?" for column in changes)  # column names are ours, not input
    c.execute(
        f"UPDATE library_assets SET updated_ns = ?{sets} WHERE id = ?",
        (now_ns, *changes.values(), asset_id),
    )


def _asset_by_id(c: sqlite3.Connection, asset_id: int) -> AssetRecord:
    row = c.execute(f"SELECT {ASSET_COLUMNS} FROM library_assets WHERE id = ?", (asset_id,))
    return _with_tags(c, [asset_of(row.fetchone())])[0]


def _with_tags(c: sqlite3.Connection, assets: list[AssetRecord]) -> list[AssetRecord]:
    """The assets with their tags and version counts filled in, in two queries."""
    if not assets:
        return assets
    by_id = {a.id: a for a in assets}
    marks = ", ".join("?" * len(by_id))
    for asset_id, tag, digest in c.execute(
        f"SELECT asset_id, tag, digest FROM library_tags WHERE asset_id IN ({marks})"
        " ORDER BY asset_id, tag",
        list(by_id),
    ):
        by_id[asset_id].tags[tag] = digest
    for asset_id, count in c.execute(
        f"SELECT asset_id, count(*) FROM library_versions WHERE asset_id IN ({marks})"
        " GROUP BY asset_id",
        list(by_id),
    ):
        by_id[asset_id].versions = count
    return assets


def _holders(c: sqlite3.Connection, asset_id: int, digest: str | None) -> list[str]:
    sql = "SELECT DISTINCT holder FROM library_holds WHERE asset_id = ?"
    args: tuple[object, ...] = (asset_id,)
    if digest is not None:
        sql += " AND digest = ?"
        args += (digest,)
    return [r[0] for r in c.execute(sql + " ORDER BY holder", args)]
