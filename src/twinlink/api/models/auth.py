"""Answers of /api/v1/auth, /api/v1/tokens and /api/v1/users. A token's secret is in an
answer once, when it is made; its hash never is."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


class UserView(BaseModel):
    username: str
    is_admin: bool
    groups: list[str]
    disabled: bool
    created: str = Field(description="ISO 8601, UTC")


class TokenView(BaseModel):
    """What the server says about any token (never its secret)."""

    id: int
    name: str
    state: Literal["active", "expired", "revoked"]
    prefix: str = Field(description="the token's first characters, to recognise it by")
    kind: str = Field(description="`api` (made by a person or script) or `session` (a login)")
    created: str = Field(description="ISO 8601, UTC")
    expires: str | None = Field(description="ISO 8601, UTC; null: it does not expire")
    last_used: str | None
    revoked: str | None


class _Secret(BaseModel):
    token: str = Field(description="the secret: shown in this answer only")


# The secret comes first in these answers, as before the models: a base listed last has its
# fields first.
class IssuedToken(TokenView, _Secret):
    pass


class _Owner(_Secret):
    username: str = Field(description="the user the token belongs to")


class IssuedTokenFor(TokenView, _Owner):
    pass


class _Session(_Secret):
    token_type: Literal["bearer"]


class LoginAnswer(TokenView, _Session):
    pass


class ListedToken(TokenView):
    username: str = Field(description="the user the token belongs to")
    current: bool = Field(description="whether it is the token of this request")


class TokenList(BaseModel):
    tokens: list[ListedToken]


class Revoked(BaseModel):
    revoked: int = Field(description="the id of the token revoked")


class UserList(BaseModel):
    users: list[UserView]


class DeletedUser(BaseModel):
    deleted: str = Field(description="the username")
