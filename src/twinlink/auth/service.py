"""Users, logins and API tokens.

A token's record and its user are cached for `TOKEN_CACHE_S` after a lookup, so a request
does not wait for the store to learn who sent it. Every change that could make a cached
answer wrong (a token revoked, a user changed, disabled or deleted) empties the cache once it
is written; expiry is checked on every use. One server process owns the store, so nothing
changes it behind this cache (the time limit is a second line of defence, not the first).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from twinlink.auth import scopes
from twinlink.auth.last_used import LastUsed
from twinlink.auth.rights import Principal
from twinlink.auth.secrets import (
    hash_password,
    hash_token,
    new_password,
    new_token,
    token_prefix,
    verify_password,
)
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    TwinlinkError,
)
from twinlink.domain.records import ApiToken, User
from twinlink.store.base import MetadataStore

log = logging.getLogger("twinlink.auth")
ADMIN_USERNAME = "admin"
TOKEN_CACHE_S = 30.0
TOKEN_CACHE_LIMIT = 10_000
# Expiry times are int64 ns (they end in 2262); a century is more than any token needs.
MAX_TOKEN_LIFETIME_S = 100 * 365 * 24 * 3600
# A run's token expires after this even if its run never ended (a server killed mid-run,
# whose next start fails the run but cannot know its token): a run longer than a year is
# not a lifecycle phase.
RUN_TOKEN_MAX_S = 366 * 24 * 3600


class AuthError(TwinlinkError):
    """Missing, unknown, expired or revoked credentials; the answer says how to send a token."""

    status = 401

    def problem_detail(self) -> str:
        return f"{self}. Send a valid token as 'Authorization: Bearer <token>'."


class ScopeError(AuthError):
    """A scoped token (a lifecycle run's) used outside its scope (auth/scopes.py)."""

    status = 403

    def problem_detail(self) -> str:
        return f"{self}."


class LoginError(AuthError):
    """A wrong username or password (without the bearer-token hint)."""

    def problem_detail(self) -> str:
        return f"{self}."


@dataclass(slots=True)
class Bootstrap:
    """What the first start created; printed once, never stored in clear."""

    username: str
    password: str | None
    token: str | None


@dataclass(slots=True)
class IssuedToken:
    token: str  # the secret, returned exactly once
    record: ApiToken


@dataclass(slots=True)
class ListedToken:
    """A token as lists show it: its record (never its secret), whose it is, and whether it
    is the one the listing request was made with."""

    record: ApiToken
    username: str
    current: bool


def now_ns() -> int:
    return time.time_ns()


class AuthService:
    def __init__(
        self, store: MetadataStore, session_ttl_s: int, last_used: LastUsed | None = None
    ) -> None:
        self.store = store
        # When each token was last used: kept in memory, written behind (last_used.py).
        self.last_used = last_used or LastUsed(store)
        self.session_ttl_ns = session_ttl_s * 1_000_000_000
        # token hash -> (token, user, when cached: monotonic s); see the module's doc
        self._tokens: dict[bytes, tuple[ApiToken, User, float]] = {}
        self.generation = 0  # bumped after every change of tokens or users
        # Called after every change, so other nodes' caches hear of it (cluster.py).
        self.changed_listeners: list[Callable[[], None]] = []

    @contextmanager
    def _changing(self) -> Iterator[None]:
        """Around a change of tokens or users: afterwards (even a failed one), no cached
        token answer survives, nor one read while the change was underway."""
        try:
            yield
        finally:
            self.forget_cached()
            for listener in self.changed_listeners:
                listener()

    def forget_cached(self) -> None:
        """No cached token answer survives, nor one being read now: after a change here, or
        one another node made (cluster.py)."""
        self.generation += 1
        self._tokens.clear()

    async def _find_token(self, token_hash: bytes) -> tuple[ApiToken, User] | None:
        cached = self._tokens.get(token_hash)
        if cached is not None and time.monotonic() - cached[2] < TOKEN_CACHE_S:
            return cached[0], cached[1]
        read_at = self.generation
        found = await self.store.find_token(token_hash)
        if found is not None and read_at == self.generation:  # unknown tokens are not kept
            if len(self._tokens) >= TOKEN_CACHE_LIMIT:
                self._tokens.clear()
            self._tokens[token_hash] = (found[0], found[1], time.monotonic())
        return found

    async def bootstrap(
        self, admin_token: str | None, admin_password: str | None
    ) -> Bootstrap | None:
        """On an empty store, create `admin` with a token; returns the secrets to print once.

        A preset `admin_token` (TWINLINK_ADMIN_TOKEN) is also ensured on later starts, so an
        automation that knows it can always get in.
        """
        created: Bootstrap | None = None
        if await self.store.count_users() == 0:
            password = admin_password or new_password()
            user = await self.store.create_user(
                ADMIN_USERNAME, hash_password(password), True, [], now_ns()
            )
            token = admin_token or new_token()
            await self._store_token(user.id, "bootstrap", token, "api", None)
            created = Bootstrap(
                ADMIN_USERNAME,
                None if admin_password else password,
                None if admin_token else token,
            )
            log.info(
                "created the first admin", extra={"event": "bootstrap", "user": ADMIN_USERNAME}
            )
        elif admin_token and await self.store.find_token(hash_token(admin_token)) is None:
            admin = await self.store.get_user_by_name(ADMIN_USERNAME)
            if admin is not None:
                await self._store_token(admin.id, "preset", admin_token, "api", None)
        return created

    async def authenticate(self, token: str, request: tuple[str, str] | None = None) -> Principal:
        """The caller of `token`, used for `request` (method, path): a scoped token is refused
        (ScopeError) on a path outside its scope, and wherever no request is given."""
        found = await self._find_token(hash_token(token))
        if found is None:
            raise AuthError("the token is not valid")
        record, user = found
        now = now_ns()
        if record.revoked_ns is not None:
            raise AuthError("the token has been revoked")
        if record.expires_ns is not None and record.expires_ns <= now:
            raise AuthError("the token has expired")
        if user.disabled:
            raise AuthError("the user is disabled")
        if record.scope is not None and (why := scopes.refusal(record.scope, request)):
            raise ScopeError(why)
        # In memory only (the cached record too): the store gets it later, in a batch, and a
        # store that cannot take it (a full disk) never fails the request.
        record.last_used_ns = now
        self.last_used.token_used(record.id, now)
        return Principal(user=user, token_id=record.id, scope=record.scope)

    async def login(self, username: str, password: str) -> IssuedToken:
        user = await self.store.get_user_by_name(username)
        if not verify_password(user.password_hash if user else None, password) or user is None:
            raise LoginError("wrong username or password")
        if user.disabled:
            raise LoginError("the user is disabled")
        return await self.issue_token(user, "login session", ttl_s=None, kind="session")

    async def issue_token(
        self, user: User, name: str, ttl_s: int | None, kind: str = "api"
    ) -> IssuedToken:
        expires = None
        if kind == "session":
            expires = now_ns() + self.session_ttl_ns
        elif ttl_s is not None:
            if not 0 < ttl_s <= MAX_TOKEN_LIFETIME_S:
                raise InvalidInputError(
                    f"a token's lifetime is 1 to {MAX_TOKEN_LIFETIME_S} s (100 years)"
                )
            expires = now_ns() + ttl_s * 1_000_000_000
        token = new_token()
        record = await self._store_token(user.id, name, token, kind, expires)
        return IssuedToken(token, record)

    async def _store_token(
        self,
        user_id: int,
        name: str,
        token: str,
        kind: str,
        expires_ns: int | None,
        scope: str | None = None,
    ) -> ApiToken:
        return await self.store.create_token(
            user_id,
            name,
            hash_token(token),
            token_prefix(token),
            kind,
            now_ns(),
            expires_ns,
            scope=scope,
        )

    async def issue_run_token(self, user_id: int, name: str, scope: str) -> IssuedToken:
        """A lifecycle run's token: `user_id`'s rights within `scope` (auth/scopes.py), kind
        `run`, until revoke_run_token (a run ends) or RUN_TOKEN_MAX_S at most."""
        user = await self.store.get_user(user_id)
        if user is None or user.disabled:
            raise ForbiddenError(f"user {user_id} (the deployment's owner) cannot run scripts")
        token = new_token()
        expires = now_ns() + RUN_TOKEN_MAX_S * 1_000_000_000
        record = await self._store_token(user.id, name, token, "run", expires, scope)
        return IssuedToken(token, record)

    async def revoke_run_token(self, token_id: int) -> None:
        with self._changing():
            await self.store.revoke_token(token_id, now_ns())

    async def revoke_token(self, principal: Principal, token_id: int) -> None:
        record = await self.store.get_token(token_id)
        if record is None or not (principal.is_admin or _owns(principal, record)):
            raise NotFoundError(f"no token {token_id}")
        with self._changing():
            await self.store.revoke_token(token_id, now_ns())

    async def list_tokens(self, principal: Principal, all_users: bool) -> list[ListedToken]:
        assert principal.user is not None
        if all_users and principal.is_admin:
            # Tokens first: a user deleted in between takes their tokens along, while one
            # created in between could otherwise have a token listed but no name.
            records = await self.store.list_tokens(None)
            names = {u.id: u.username for u in await self.store.list_users()}
        else:
            names = {principal.user.id: principal.user.username}
            records = await self.store.list_tokens(principal.user.id)
        for record in records:
            record.last_used_ns = self.last_used.token_time(record.id, record.last_used_ns)
        return [
            ListedToken(t, names.get(t.user_id, ""), t.id == principal.token_id) for t in records
        ]

    async def create_user(
        self, username: str, password: str | None, is_admin: bool, groups: list[str]
    ) -> User:
        if await self.store.get_user_by_name(username) is not None:
            raise ConflictError(f"a user named {username!r} already exists")
        return await self.store.create_user(
            username, hash_password(password) if password else None, is_admin, groups, now_ns()
        )

    async def update_user(
        self,
        username: str,
        *,
        password: str | None = None,
        is_admin: bool | None = None,
        groups: list[str] | None = None,
        disabled: bool | None = None,
    ) -> User:
        user = await self.require_user(username)
        with self._changing():
            if password or disabled:
                # A new password or a disabled account ends every login session of the user.
                await self.store.revoke_tokens(user.id, "session", now_ns())
            updated = await self.store.update_user(
                user.id,
                password_hash=hash_password(password) if password else None,
                is_admin=is_admin,
                groups=groups,
                disabled=disabled,
            )
        assert updated is not None
        return updated

    async def check_current_password(self, username: str, current_password: str | None) -> None:
        """Before users change their own password: the one they have now must come with it,
        so a token left behind in a browser cannot lock its owner out. A user without a
        password (one who signs in with tokens only) has none to give."""
        user = await self.require_user(username)
        if user.password_hash is None:
            return
        if not current_password:
            raise InvalidInputError(
                "to change your own password, send the one you have now as current_password"
            )
        if not verify_password(user.password_hash, current_password):
            raise ForbiddenError("the current password is wrong; nothing was changed")

    async def delete_user(self, user: User) -> bool:
        """Delete the user with their tokens and roles; False when already gone."""
        with self._changing():
            return await self.store.delete_user(user.id)

    async def require_user(self, username: str) -> User:
        user = await self.store.get_user_by_name(username)
        if user is None:
            raise NotFoundError(f"no user named {username!r}")
        return user


def _owns(principal: Principal, record: ApiToken) -> bool:
    return principal.user is not None and principal.user.id == record.user_id
