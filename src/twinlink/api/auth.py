"""/api/v1/auth, /api/v1/tokens, /api/v1/users: logins, API tokens and users."""

from __future__ import annotations

import time
from typing import Annotated

from fastapi import APIRouter, Query
from pydantic import AfterValidator, BaseModel, Field

from twinlink.api.deps import Admin, Auth, Caller
from twinlink.api.models.auth import (
    DeletedUser,
    IssuedToken,
    IssuedTokenFor,
    ListedToken,
    LoginAnswer,
    Revoked,
    TokenList,
    TokenView,
    UserList,
    UserView,
)
from twinlink.api.models.problem import problems
from twinlink.api.params import RowId
from twinlink.api.routing import ExactJsonRoute
from twinlink.auth.rights import Principal
from twinlink.auth.service import MAX_TOKEN_LIFETIME_S, AuthError
from twinlink.auth.service import ListedToken as ListedRecord
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.records import ApiToken, User
from twinlink.registry.build import human_time, human_time_or_none

router = APIRouter(
    prefix="/api/v1",
    tags=["auth"],
    route_class=ExactJsonRoute,
    responses=problems(401, 422, 503),
)
# Routes that change users or tokens: a name may be taken, the disk may be full.
CHANGING = problems(409, 507)

_GROUP = r"^[A-Za-z0-9][A-Za-z0-9_.:-]{0,63}$"


def _not_a_level(name: str) -> str:
    # A group is named like a privacy level; "public" and "private" are levels, never groups.
    if name.lower() in ("public", "private"):
        raise ValueError(f"{name!r} is a privacy level, not a group name")
    return name


GroupName = Annotated[str, Field(pattern=_GROUP), AfterValidator(_not_a_level)]


class Login(BaseModel):
    username: str = Field(min_length=1, max_length=128)
    password: str = Field(min_length=1, max_length=1024)


class NewToken(BaseModel):
    name: str = Field(min_length=1, max_length=128, description="what the token is for")
    expires_in_s: int | None = Field(
        None,
        gt=0,
        le=MAX_TOKEN_LIFETIME_S,
        description="lifetime in seconds, at most 100 years; none = no expiry",
    )


class NewUser(BaseModel):
    username: str = Field(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9][A-Za-z0-9_.@-]*$")
    password: str | None = Field(None, min_length=8, max_length=1024)
    is_admin: bool = False
    groups: list[GroupName] = Field(default_factory=list)


class UserChange(BaseModel):
    password: str | None = Field(None, min_length=8, max_length=1024)
    current_password: str | None = Field(
        None,
        max_length=1024,
        description="the password you have now; needed to change your own password, unless"
        " you have none",
    )
    is_admin: bool | None = None
    groups: list[GroupName] | None = None
    disabled: bool | None = None


def user_view(u: User) -> UserView:
    return UserView(
        username=u.username,
        is_admin=u.is_admin,
        groups=u.groups,
        disabled=u.disabled,
        created=human_time(u.created_ns),
    )


def token_view(t: ApiToken) -> TokenView:
    now = time.time_ns()
    state = "active"
    if t.revoked_ns is not None:
        state = "revoked"
    elif t.expires_ns is not None and t.expires_ns <= now:
        state = "expired"
    return TokenView(
        id=t.id,
        name=t.name,
        state=state,
        prefix=t.prefix,
        kind=t.kind,
        created=human_time(t.created_ns),
        expires=human_time_or_none(t.expires_ns),
        last_used=human_time_or_none(t.last_used_ns),
        revoked=human_time_or_none(t.revoked_ns),
    )


def listed_token_view(listed: ListedRecord) -> ListedToken:
    return ListedToken(
        **token_view(listed.record).model_dump(),
        username=listed.username,
        current=listed.current,
    )


@router.post(
    "/auth/login",
    summary="Exchange a username and password for a session token",
    responses=problems(507),
)
async def login(body: Login, auth: Auth) -> LoginAnswer:
    issued = await auth.login(body.username, body.password)
    fields = token_view(issued.record).model_dump()
    return LoginAnswer(token=issued.token, token_type="bearer", **fields)


@router.post(
    "/auth/logout",
    summary="Revoke the token this request was made with",
    responses=problems(507),
)
async def logout(caller: Caller, auth: Auth) -> Revoked:
    assert caller.token_id is not None
    await auth.revoke_token(caller, caller.token_id)
    return Revoked(revoked=caller.token_id)


@router.get("/auth/me", summary="Who the caller is")
async def me(caller: Caller) -> UserView:
    assert caller.user is not None
    return user_view(caller.user)


@router.get(
    "/tokens",
    summary="The caller's API tokens (admins: everyone's with all=true)",
    responses=problems(403),
)
async def list_tokens(caller: Caller, auth: Auth, all: bool = False) -> TokenList:
    return TokenList(tokens=[listed_token_view(t) for t in await auth.list_tokens(caller, all)])


@router.post(
    "/tokens",
    status_code=201,
    summary="Create an API token; the secret is shown once",
    responses=CHANGING,
)
async def create_token(body: NewToken, caller: Caller, auth: Auth) -> IssuedToken:
    assert caller.user is not None
    issued = await auth.issue_token(caller.user, body.name, body.expires_in_s)
    return IssuedToken(token=issued.token, **token_view(issued.record).model_dump())


@router.post(
    "/users/{username}/tokens",
    status_code=201,
    summary="Create an API token for another user, e.g. a service account (admins)",
    responses={**problems(403, 404), **CHANGING},
)
async def create_token_for(username: str, body: NewToken, _: Admin, auth: Auth) -> IssuedTokenFor:
    user = await auth.require_user(username)
    issued = await auth.issue_token(user, body.name, body.expires_in_s)
    fields = token_view(issued.record).model_dump()
    return IssuedTokenFor(token=issued.token, username=user.username, **fields)


@router.delete(
    "/tokens/{token_id}",
    summary="Revoke an API token",
    responses={**problems(403, 404), **CHANGING},
)
async def revoke_token(token_id: RowId, caller: Caller, auth: Auth) -> Revoked:
    await auth.revoke_token(caller, token_id)
    return Revoked(revoked=token_id)


@router.get("/users", summary="All users (admins)", responses=problems(403))
async def list_users(_: Admin, auth: Auth) -> UserList:
    return UserList(users=[user_view(u) for u in await auth.store.list_users()])


@router.post(
    "/users",
    status_code=201,
    summary="Create a user (admins)",
    responses={**problems(403), **CHANGING},
)
async def create_user(body: NewUser, _: Admin, auth: Auth) -> UserView:
    user = await auth.create_user(body.username, body.password, body.is_admin, body.groups)
    return user_view(user)


@router.patch(
    "/users/{username}",
    summary="Change a user (admins; users may change their password)",
    responses={**problems(403, 404), **CHANGING},
)
async def update_user(username: str, body: UserChange, caller: Caller, auth: Auth) -> UserView:
    _may_change(caller, username, body)
    if body.password and _is_self(caller, username):
        await auth.check_current_password(username, body.current_password)
    return user_view(
        await auth.update_user(
            username,
            password=body.password,
            is_admin=body.is_admin,
            groups=body.groups,
            disabled=body.disabled,
        )
    )


@router.delete(
    "/users/{username}",
    summary="Delete a user (admins)",
    responses={**problems(403, 404), **CHANGING},
)
async def delete_user(
    username: str, caller: Admin, auth: Auth, force: Annotated[bool, Query()] = False
) -> DeletedUser:
    user = await auth.require_user(username)
    if caller.user is not None and user.id == caller.user.id and not force:
        raise ForbiddenError("refusing to delete yourself; pass force=true if you mean it")
    if not await auth.delete_user(user):
        raise NotFoundError(f"no user named {username!r}")
    return DeletedUser(deleted=username)


def _may_change(caller: Principal, username: str, body: UserChange) -> None:
    if caller.is_admin:
        return
    if caller.user is None:
        raise AuthError("a token is required")
    others = (body.is_admin, body.groups, body.disabled)
    if not _is_self(caller, username) or any(x is not None for x in others):
        raise ForbiddenError("only admins change users; you may change your own password")


def _is_self(caller: Principal, username: str) -> bool:
    return caller.user is not None and caller.user.username.lower() == username.lower()
