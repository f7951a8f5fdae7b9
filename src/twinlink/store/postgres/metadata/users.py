"""Users and API tokens in PostgreSQL."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import asyncpg
import orjson

from twinlink.domain.records import ApiToken, User
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.rows import TOKEN_COLUMNS, USER_COLUMNS, token_of, user_of


class UserTables:
    db: PostgresDatabase

    async def _fetchrow(self, sql: str, *args: Any) -> asyncpg.Record | None:
        async with self.db.connection() as conn:
            return await conn.fetchrow(sql, *args)

    async def count_users(self) -> int:
        async with self.db.connection() as conn:
            return int(await conn.fetchval("SELECT count(*) FROM users"))

    async def create_user(
        self,
        username: str,
        password_hash: str | None,
        is_admin: bool,
        groups: list[str],
        now_ns: int,
    ) -> User:
        async with self.db.transaction() as conn:
            row = await conn.fetchrow(
                "INSERT INTO users (username, password_hash, is_admin, groups_json, created_ns)"
                f" VALUES ($1, $2, $3, $4, $5) RETURNING {USER_COLUMNS}",
                username, password_hash, is_admin, orjson.dumps(groups).decode(), now_ns,
            )  # fmt: skip
        assert row is not None
        return user_of(row)

    async def get_user(self, user_id: int) -> User | None:
        row = await self._fetchrow(f"SELECT {USER_COLUMNS} FROM users WHERE id = $1", user_id)
        return user_of(row) if row else None

    async def get_user_by_name(self, username: str) -> User | None:
        # SQLite's users.username is COLLATE NOCASE: a name is found whatever its case.
        row = await self._fetchrow(
            f"SELECT {USER_COLUMNS} FROM users WHERE lower(username) = lower($1)", username
        )
        return user_of(row) if row else None

    async def list_users(self) -> list[User]:
        async with self.db.connection() as conn:
            rows = await conn.fetch(f"SELECT {USER_COLUMNS} FROM users ORDER BY id")
        return [user_of(r) for r in rows]

    async def update_user(
        self,
        user_id: int,
        *,
        password_hash: str | None = None,
        is_admin: bool | None = None,
        groups: list[str] | None = None,
        disabled: bool | None = None,
    ) -> User | None:
        sets: list[str] = []
        args: list[object] = [user_id]
        for column, value in (
            ("password_hash", password_hash),
            ("is_admin", is_admin),
            ("groups_json", None if groups is None else orjson.dumps(groups).decode()),
            ("disabled", disabled),
        ):
            if value is not None:
                args.append(value)
                sets.append(f"{column} = ${len(args)}")
        async with self.db.transaction() as conn:
            if sets:
                await conn.execute(f"UPDATE users SET {', '.join(sets)} WHERE id = $1", *args)
            row = await conn.fetchrow(f"SELECT {USER_COLUMNS} FROM users WHERE id = $1", user_id)
        return user_of(row) if row else None

    async def delete_user(self, user_id: int) -> bool:
        async with self.db.transaction() as conn:
            status = await conn.execute("DELETE FROM users WHERE id = $1", user_id)
        return affected(status) > 0

    async def create_token(
        self,
        user_id: int,
        name: str,
        token_hash: bytes,
        prefix: str,
        kind: str,
        now_ns: int,
        expires_ns: int | None,
        *,
        scope: str | None = None,
    ) -> ApiToken:
        async with self.db.transaction() as conn:
            row = await conn.fetchrow(
                "INSERT INTO api_tokens (user_id, name, token_hash, prefix, kind, created_ns,"
                f" expires_ns, scope) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)"
                f" RETURNING {TOKEN_COLUMNS}",
                user_id, name, token_hash, prefix, kind, now_ns, expires_ns, scope,
            )  # fmt: skip
        assert row is not None
        return token_of(row)

    async def find_token(self, token_hash: bytes) -> tuple[ApiToken, User] | None:
        user_columns = ", ".join(f"u.{c} AS u_{c}" for c in USER_COLUMNS.split(", "))
        token_columns = ", ".join(f"k.{c}" for c in TOKEN_COLUMNS.split(", "))
        row = await self._fetchrow(
            f"SELECT {token_columns}, {user_columns} FROM api_tokens k"
            " JOIN users u ON u.id = k.user_id WHERE k.token_hash = $1",
            token_hash,
        )
        if row is None:
            return None
        user = {c: row[f"u_{c}"] for c in USER_COLUMNS.split(", ")}
        return token_of(row), user_of(user)

    async def touch_tokens(self, times: Mapping[int, int]) -> None:
        """Record when tokens were last used ({token id: ns}), never moving a time back."""
        async with self.db.transaction() as conn:
            await conn.execute(
                "UPDATE api_tokens k SET last_used_ns = t.ns FROM unnest($1::bigint[],"
                " $2::bigint[]) AS t(id, ns) WHERE k.id = t.id"
                " AND (k.last_used_ns IS NULL OR k.last_used_ns < t.ns)",
                list(times), list(times.values()),
            )  # fmt: skip

    async def list_tokens(self, user_id: int | None) -> list[ApiToken]:
        async with self.db.connection() as conn:
            if user_id is None:
                rows = await conn.fetch(f"SELECT {TOKEN_COLUMNS} FROM api_tokens ORDER BY id")
            else:
                rows = await conn.fetch(
                    f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE user_id = $1 ORDER BY id",
                    user_id,
                )
        return [token_of(r) for r in rows]

    async def get_token(self, token_id: int) -> ApiToken | None:
        row = await self._fetchrow(
            f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE id = $1", token_id
        )
        return token_of(row) if row else None

    async def revoke_tokens(self, user_id: int, kind: str, now_ns: int) -> int:
        async with self.db.transaction() as conn:
            status = await conn.execute(
                "UPDATE api_tokens SET revoked_ns = $1 WHERE user_id = $2 AND kind = $3"
                " AND revoked_ns IS NULL",
                now_ns, user_id, kind,
            )  # fmt: skip
        return affected(status)

    async def revoke_token(self, token_id: int, now_ns: int) -> bool:
        async with self.db.transaction() as conn:
            status = await conn.execute(
                "UPDATE api_tokens SET revoked_ns = $1 WHERE id = $2 AND revoked_ns IS NULL",
                now_ns, token_id,
            )  # fmt: skip
        return affected(status) > 0


def affected(status: str) -> int:
    """The rows a command changed, from its status ("UPDATE 3", "DELETE 1")."""
    return int(status.rsplit(" ", 1)[-1])
