"""The library's assets, versions, tags and holds in PostgreSQL (migration 0050)."""

from __future__ import annotations

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
from twinlink.store.postgres.db import Connection, PostgresDatabase

# The advisory lock of the library's blobs (beside twins.py's relations lock): a sweep on
# one node and a push on another take turns.
_BLOB_LOCK = 0x7477_6C6E_6B00_0020
_LIKE_ESCAPE = str.maketrans({"%": r"\%", "_": r"\_", "\\": r"\\"})


class LibraryTables:
    db: PostgresDatabase

    async def get_asset(self, scope: str, kind: str, name: str) -> AssetRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(
                f"SELECT {ASSET_COLUMNS} FROM library_assets"
                " WHERE scope = $1 AND kind = $2 AND name = $3",
                scope, kind, name,
            )  # fmt: skip
            return (await _with_tags(conn, [asset_of(row)]))[0] if row else None

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

        def arg(value: object) -> str:
            args.append(value)
            return f"${len(args)}"

        if scopes is not None:
            where.append(f"scope = ANY({arg(scopes)}::text[])")
        if kind is not None:
            where.append(f"kind = {arg(kind)}")
        if text:
            like = arg(f"%{text.lower().translate(_LIKE_ESCAPE)}%")
            where.append(
                f"(lower(name) LIKE {like} OR lower(description) LIKE {like}"
                f" OR lower(keywords) LIKE {like})"
            )
        if after is not None:
            where.append(
                f"(scope, kind, name) > ({arg(after[0])}, {arg(after[1])}, {arg(after[2])})"
            )
        sql = f"SELECT {ASSET_COLUMNS} FROM library_assets"
        sql += f" WHERE {' AND '.join(where)}" if where else ""
        sql += f" ORDER BY scope, kind, name LIMIT {arg(limit)}"
        async with self.db.connection() as conn:
            return await _with_tags(conn, [asset_of(r) for r in await conn.fetch(sql, *args)])

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

        def arg(value: object) -> str:
            args.append(value)
            return f"${len(args)}"

        if scopes is not None:
            where.append(f"scope = ANY({arg(scopes)}::text[])")
        for term in terms:
            like = arg(f"%{term.translate(_LIKE_ESCAPE)}%")
            where.append(
                f"(lower(name) LIKE {like} OR lower(description) LIKE {like}"
                f" OR lower(keywords) LIKE {like})"
            )
            in_name.append(f"lower(name) LIKE {like}")
        if keyword:
            where.append(f"keywords::jsonb ? {arg(keyword)}")
        cond = f" WHERE {' AND '.join(where)}" if where else ""
        first = f"CASE WHEN {' AND '.join(in_name)} THEN 0 ELSE 1 END, " if in_name else ""
        async with self.db.connection() as conn:
            total = await conn.fetchval(f"SELECT count(*) FROM library_assets{cond}", *args)
            rows = await conn.fetch(
                f"SELECT {ASSET_COLUMNS} FROM library_assets{cond}"
                f" ORDER BY {first}scope, kind, name LIMIT {arg(limit)} OFFSET {arg(offset)}",
                *args,
            )
            return await _with_tags(conn, [asset_of(r) for r in rows]), int(total)

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
        async with self.db.transaction() as conn:
            # Two pushes creating the same asset at once: one inserts, both find it.
            await conn.execute(
                "INSERT INTO library_assets (scope, kind, name, created_by, created_ns,"
                " updated_ns) VALUES ($1, $2, $3, $4, $5, $5)"
                " ON CONFLICT (scope, kind, name) DO NOTHING",
                scope, kind, name, version.created_by, now_ns,
            )  # fmt: skip
            asset_id = await conn.fetchval(
                "SELECT id FROM library_assets WHERE scope = $1 AND kind = $2 AND name = $3",
                scope, kind, name,
            )  # fmt: skip
            inserted = await conn.fetchval(
                "INSERT INTO library_versions (asset_id, digest, files, size, meta, created_by,"
                " created_ns) VALUES ($1, $2, $3, $4, $5, $6, $7)"
                " ON CONFLICT (asset_id, digest) DO NOTHING RETURNING true",
                asset_id, version.digest, files_json(version.files), version.size,
                orjson.dumps(version.meta).decode(), version.created_by, now_ns,
            )  # fmt: skip
            for tag in tags:
                await _set_tag(conn, asset_id, tag, version.digest, now_ns)
            await _update(conn, asset_id, fields, now_ns)
            stored = await conn.fetchrow(
                f"SELECT {VERSION_COLUMNS} FROM library_versions"
                " WHERE asset_id = $1 AND digest = $2",
                asset_id, version.digest,
            )  # fmt: skip
            asset = await _asset_by_id(conn, asset_id)
        assert stored is not None and asset is not None
        return asset, version_of(stored), bool(inserted)

    async def update_asset(
        self, asset_id: int, fields: AssetFields, now_ns: int
    ) -> AssetRecord | None:
        async with self.db.transaction() as conn:
            if await conn.fetchval("SELECT 1 FROM library_assets WHERE id = $1", asset_id):
                await _update(conn, asset_id, fields, now_ns)
                return await _asset_by_id(conn, asset_id)
        return None

    async def delete_asset(self, asset_id: int) -> list[str] | None:
        async with self.db.transaction() as conn:
            # Locked first: a hold added meanwhile waits for the delete (and then fails).
            await conn.execute("SELECT 1 FROM library_assets WHERE id = $1 FOR UPDATE", asset_id)
            holders = await _holders(conn, asset_id, None)
            if holders:
                return holders
            await conn.execute("DELETE FROM library_assets WHERE id = $1", asset_id)
        return None

    async def list_versions(self, asset_id: int) -> list[VersionRecord]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                f"SELECT {VERSION_COLUMNS} FROM library_versions WHERE asset_id = $1"
                " ORDER BY created_ns DESC, digest",
                asset_id,
            )
        return [version_of(r) for r in rows]

    async def get_version(self, asset_id: int, digest: str) -> VersionRecord | None:
        async with self.db.connection() as conn:
            row = await conn.fetchrow(
                f"SELECT {VERSION_COLUMNS} FROM library_versions"
                " WHERE asset_id = $1 AND digest = $2",
                asset_id, digest,
            )  # fmt: skip
        return version_of(row) if row else None

    async def find_digests(self, asset_id: int, prefix: str) -> list[str]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "SELECT digest FROM library_versions WHERE asset_id = $1 AND digest >= $2"
                " AND digest < $3 ORDER BY digest LIMIT 5",
                asset_id, prefix, prefix + "~",
            )  # fmt: skip
        return [r["digest"] for r in rows]

    async def delete_version(self, asset_id: int, digest: str) -> list[str] | None:
        async with self.db.transaction() as conn:
            await conn.execute(
                "SELECT 1 FROM library_versions WHERE asset_id = $1 AND digest = $2 FOR UPDATE",
                asset_id, digest,
            )  # fmt: skip
            holders = await _holders(conn, asset_id, digest)
            if holders:
                return holders
            await conn.execute(
                "DELETE FROM library_versions WHERE asset_id = $1 AND digest = $2",
                asset_id, digest,
            )  # fmt: skip
        return None

    async def set_tag(self, asset_id: int, tag: str, digest: str, now_ns: int) -> None:
        async with self.db.transaction() as conn:
            await _set_tag(conn, asset_id, tag, digest, now_ns)

    async def delete_tag(self, asset_id: int, tag: str) -> bool:
        async with self.db.transaction() as conn:
            status = await conn.execute(
                "DELETE FROM library_tags WHERE asset_id = $1 AND tag = $2", asset_id, tag
            )
        return status != "DELETE 0"

    async def add_holds(self, holder: str, versions: Iterable[tuple[int, str]]) -> None:
        rows = [(asset_id, digest, holder) for asset_id, digest in versions]
        async with self.db.transaction() as conn:
            await conn.executemany(
                "INSERT INTO library_holds (asset_id, digest, holder) VALUES ($1, $2, $3)"
                " ON CONFLICT DO NOTHING",
                rows,
            )

    async def release_holds(self, holder: str) -> int:
        async with self.db.transaction() as conn:
            status = await conn.execute("DELETE FROM library_holds WHERE holder = $1", holder)
        return int(status.split()[-1])

    async def list_holders(self, asset_id: int, digest: str | None = None) -> list[str]:
        async with self.db.connection() as conn:
            return await _holders(conn, asset_id, digest)

    async def referenced_blobs(self, sha256s: Iterable[str]) -> set[str]:
        wanted = sorted(set(sha256s))
        if not wanted:
            return set()
        async with self.db.connection() as conn:
            rows = await conn.fetch(
                "SELECT DISTINCT f ->> 'sha256' AS sha256"
                " FROM library_versions v, jsonb_array_elements(v.files::jsonb) f"
                " WHERE f ->> 'sha256' = ANY($1::text[])",
                wanted,
            )
        return {r["sha256"] for r in rows}

    @asynccontextmanager
    async def blob_lock(self) -> AsyncIterator[None]:
        # A session lock on a connection of its own: held across the blob deletes or the
        # push's last step, which are not one transaction.
        async with self.db.connection() as conn:
            await conn.execute("SELECT pg_advisory_lock($1)", _BLOB_LOCK)
            try:
                yield
            finally:
                await conn.execute("SELECT pg_advisory_unlock($1)", _BLOB_LOCK)


async def _set_tag(conn: Connection, asset_id: int, tag: str, digest: str, now_ns: int) -> None:
    await conn.execute(
        "INSERT INTO library_tags (asset_id, tag, digest, updated_ns) VALUES ($1, $2, $3, $4)"
        " ON CONFLICT (asset_id, tag) DO UPDATE SET digest = excluded.digest,"
        " updated_ns = excluded.updated_ns",
        asset_id, tag, digest, now_ns,
    )  # fmt: skip
    await conn.execute("UPDATE library_assets SET updated_ns = $1 WHERE id = $2", now_ns, asset_id)


async def _update(conn: Connection, asset_id: int, fields: AssetFields, now_ns: int) -> None:
    changes = fields.as_dict()
    if "keywords" in changes:
        changes["keywords"] = orjson.dumps(changes["keywords"]).decode()
    # column names are ours (AssetFields), not input
    sets = "".join(f", {column} = ${i}" for i, column in enumerate(changes, start=3))
    await conn.execute(
        f"UPDATE library_assets SET updated_ns = $1{sets} WHERE id = $2",
        now_ns, asset_id, *changes.values(),
    )  # fmt: skip


async def _asset_by_id(conn: Connection, asset_id: int) -> AssetRecord | None:
    row = await conn.fetchrow(f"SELECT {ASSET_COLUMNS} FROM library_assets WHERE id = $1", asset_id)
    return (await _with_tags(conn, [asset_of(row)]))[0] if row else None


async def _with_tags(conn: Connection, assets: list[AssetRecord]) -> list[AssetRecord]:
    """The assets with their tags and version counts filled in, in two queries."""
    if not assets:
        return assets
    by_id = {a.id: a for a in assets}
    ids = list(by_id)
    for row in await conn.fetch(
        "SELECT asset_id, tag, digest FROM library_tags WHERE asset_id = ANY($1::bigint[])"
        " ORDER BY asset_id, tag",
        ids,
    ):
        by_id[row["asset_id"]].tags[row["tag"]] = row["digest"]
    for row in await conn.fetch(
        "SELECT asset_id, count(*) AS n FROM library_versions"
        " WHERE asset_id = ANY($1::bigint[]) GROUP BY asset_id",
        ids,
    ):
        by_id[row["asset_id"]].versions = row["n"]
    return assets


async def _holders(conn: Connection, asset_id: int, digest: str | None) -> list[str]:
    if digest is None:
        rows = await conn.fetch(
            "SELECT DISTINCT holder FROM library_holds WHERE asset_id = $1 ORDER BY holder",
            asset_id,
        )
    else:
        rows = await conn.fetch(
            "SELECT DISTINCT holder FROM library_holds WHERE asset_id = $1 AND digest = $2"
            " ORDER BY holder",
            asset_id, digest,
        )  # fmt: skip
    return [r["holder"] for r in rows]
