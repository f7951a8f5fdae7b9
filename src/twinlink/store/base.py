"""The interface every metadata store implements (SQLite now, PostgreSQL later).

Services depend on this protocol only; `app.py` picks the implementation.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any, Protocol

from twinlink.store.records import (
    ApiToken,
    Edge,
    SearchResult,
    TwinRecord,
    TwinWrite,
    User,
    Visibility,
)


class MetadataStore(Protocol):
    async def open(self) -> None: ...
    async def close(self) -> None: ...
    async def ping(self) -> bool: ...

    # users and tokens
    async def count_users(self) -> int: ...
    async def create_user(
        self,
        username: str,
        password_hash: str | None,
        is_admin: bool,
        groups: list[str],
        now_ns: int,
    ) -> User: ...
    async def get_user(self, user_id: int) -> User | None: ...
    async def get_user_by_name(self, username: str) -> User | None: ...
    async def list_users(self) -> list[User]: ...
    async def update_user(
        self,
        user_id: int,
        *,
        password_hash: str | None = None,
        is_admin: bool | None = None,
        groups: list[str] | None = None,
        disabled: bool | None = None,
    ) -> User | None: ...
    async def delete_user(self, user_id: int) -> bool: ...
    async def create_token(
        self,
        user_id: int,
        name: str,
        token_hash: bytes,
        prefix: str,
        kind: str,
        now_ns: int,
        expires_ns: int | None,
    ) -> ApiToken: ...
    async def find_token(self, token_hash: bytes) -> tuple[ApiToken, User] | None: ...
    async def touch_token(self, token_id: int, now_ns: int) -> None: ...
    async def list_tokens(self, user_id: int | None) -> list[ApiToken]: ...
    async def get_token(self, token_id: int) -> ApiToken | None: ...
    async def revoke_token(self, token_id: int, now_ns: int) -> bool: ...

    # twins, parts, roles, relations
    async def get_twin(self, slug: str) -> TwinRecord | None: ...
    async def get_twin_by_dt_id(self, dt_id: str) -> TwinRecord | None: ...
    async def get_twins_by_dt_ids(self, dt_ids: Iterable[str]) -> dict[str, TwinRecord]: ...
    async def list_twins(
        self,
        vis: Visibility,
        *,
        limit: int,
        after_slug: str | None = None,
        keyword: str | None = None,
        name_contains: str | None = None,
        role_user_id: int | None = None,
    ) -> list[TwinRecord]: ...
    async def count_twins(self) -> int: ...
    async def get_parts(self, twin_id: int) -> dict[str, dict[str, Any]]: ...
    async def save_twin(self, w: TwinWrite) -> TwinRecord: ...
    async def delete_twins(self, twins: list[TwinRecord]) -> None: ...
    async def edges_touching(self, dt_ids: Iterable[str]) -> list[Edge]: ...
    async def descendants(self, roots: Iterable[str], exclude: str) -> set[str]: ...
    async def get_role(self, twin_id: int, user_id: int) -> str | None: ...
    async def list_roles(self, twin_id: int) -> list[tuple[int, str, str]]: ...
    async def set_role(self, twin_id: int, user_id: int, role: str | None) -> None: ...

    # search
    async def search(
        self,
        vis: Visibility,
        terms: list[str],
        *,
        keyword: str | None,
        limit: int,
        offset: int,
        facet_limit: int = 25,
    ) -> SearchResult: ...
