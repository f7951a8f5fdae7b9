"""Users and API tokens in SQLite."""

from __future__ import annotations

import sqlite3
from collections.abc import Mapping

import orjson

from twinlink.domain.records import ApiToken, User
from twinlink.store.rows import TOKEN_COLUMNS, USER_COLUMNS, token_of, user_of
from twinlink.store.sqlite.db import Database


class UserTables:
    db: Database

    async def count_users(self) -> int:
        return await self.db.read(lambda c: c.execute("SELECT count(*) FROM users").fetchone()[0])

    async def create_user(
        self,
        username: str,
        password_hash: str | None,
        is_admin: bool,
        groups: list[str],
        now_ns: int,
    ) -> User:
        def _create(c: sqlite3.Connection) -> User:
            cur = c.execute(
                "INSERT INTO users(username, password_hash, is_admin, groups_json, created_ns)"
                " VALUES (?, ?, ?, ?, ?)",
                (username, password_hash, int(is_admin), orjson.dumps(groups).decode(), now_ns),
            )
            row = c.execute(
                f"SELECT {USER_COLUMNS} FROM users WHERE id = ?", (cur.lastrowid,)
            ).fetchone()
            return user_of(row)

        return await self.db.write(_create)

    async def get_user(self, user_id: int) -> User | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {USER_COLUMNS} FROM users WHERE id = ?", (user_id,)
            ).fetchone()
        )
        return user_of(row) if row else None

    async def get_user_by_name(self, username: str) -> User | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {USER_COLUMNS} FROM users WHERE username = ?", (username,)
            ).fetchone()
        )
        return user_of(row) if row else None

    async def list_users(self) -> list[User]:
        rows = await self.db.read(
            lambda c: c.execute(f"SELECT {USER_COLUMNS} FROM users ORDER BY id").fetchall()
        )
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
        args: list[object] = []
        for column, value in (
            ("password_hash", password_hash),
            ("is_admin", None if is_admin is None else int(is_admin)),
            ("groups_json", None if groups is None else orjson.dumps(groups).decode()),
            ("disabled", None if disabled is None else int(disabled)),
        ):
            if value is not None:
                sets.append(f"{column} = ?")
                args.append(value)

        def _update(c: sqlite3.Connection) -> User | None:
            if sets:
                c.execute(f"UPDATE users SET {', '.join(sets)} WHERE id = ?", (*args, user_id))
            row = c.execute(f"SELECT {USER_COLUMNS} FROM users WHERE id = ?", (user_id,)).fetchone()
            return user_of(row) if row else None

        return await self.db.write(_update)

    async def delete_user(self, user_id: int) -> bool:
        return await self.db.write(
            lambda c: c.execute("DELETE FROM users WHERE id = ?", (user_id,)).rowcount > 0
        )

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
        def _create(c: sqlite3.Connection) -> ApiToken:
            cur = c.execute(
                "INSERT INTO api_tokens(user_id, name, token_hash, prefix, kind, created_ns,"
                " expires_ns, scope) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (user_id, name, token_hash, prefix, kind, now_ns, expires_ns, scope),
            )
            row = c.execute(
                f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE id = ?", (cur.lastrowid,)
            ).fetchone()
            return token_of(row)

        return await self.db.write(_create)

    async def find_token(self, token_hash: bytes) -> tuple[ApiToken, User] | None:
        def _find(c: sqlite3.Connection) -> tuple[ApiToken, User] | None:
            row = c.execute(
                f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE token_hash = ?", (token_hash,)
            ).fetchone()
            if row is None:
                return None
            user = c.execute(
                f"SELECT {USER_COLUMNS} FROM users WHERE id = ?", (row["user_id"],)
            ).fetchone()
            return (token_of(row), user_of(user)) if user else None

        return await self.db.read(_find)

    async def touch_tokens(self, times: Mapping[int, int]) -> None:
        """Record when tokens were last used ({token id: ns}), never moving a time back."""
        rows = [(ns, token_id, ns) for token_id, ns in times.items()]
        await self.db.write(
            lambda c: c.executemany(
                "UPDATE api_tokens SET last_used_ns = ? WHERE id = ?"
                " AND (last_used_ns IS NULL OR last_used_ns < ?)",
                rows,
            )
        )

    async def list_tokens(self, user_id: int | None) -> list[ApiToken]:
        def _list(c: sqlite3.Connection) -> list[sqlite3.Row]:
            if user_id is None:
                return c.execute(f"SELECT {TOKEN_COLUMNS} FROM api_tokens ORDER BY id").fetchall()
            return c.execute(
                f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE user_id = ? ORDER BY id", (user_id,)
            ).fetchall()

        return [token_of(r) for r in await self.db.read(_list)]

    async def get_token(self, token_id: int) -> ApiToken | None:
        row = await self.db.read(
            lambda c: c.execute(
                f"SELECT {TOKEN_COLUMNS} FROM api_tokens WHERE id = ?", (token_id,)
            ).fetchone()
        )
        return token_of(row) if row else None

    async def revoke_tokens(self, user_id: int, kind: str, now_ns: int) -> int:
        return await self.db.write(
            lambda c: (
                c.execute(
                    "UPDATE api_tokens SET revoked_ns = ? WHERE user_id = ? AND kind = ?"
                    " AND revoked_ns IS NULL",
                    (now_ns, user_id, kind),
                ).rowcount
            )
        )

    async def revoke_token(self, token_id: int, now_ns: int) -> bool:
        return await self.db.write(
            lambda c: (
                c.execute(
                    "UPDATE api_tokens SET revoked_ns = ? WHERE id = ? AND revoked_ns IS NULL",
                    (now_ns, token_id),
                ).rowcount
                > 0
            )
        )
