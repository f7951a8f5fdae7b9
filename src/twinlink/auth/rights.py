"""Who may see and change what. One place, so every route applies the same rules.

Platform admins may do anything. On a twin: viewers read it, editors also change its document,
owners also delete it and grant roles. Document parts: `public` is for everyone, `private`
for owners and editors, any other level (a group) for anyone with a role on the twin and
for members of the user group of that name.
"""

from __future__ import annotations

from dataclasses import dataclass

from twinlink.domain.records import ROLE_RANK, User, Visibility


@dataclass(frozen=True, slots=True)
class Principal:
    """The caller: a user, or nobody (`user is None`) for unauthenticated public reads."""

    user: User | None
    token_id: int | None = None
    scope: str | None = None  # a scoped token's (auth/scopes.py): a run's `twin:<slug>`

    @property
    def is_admin(self) -> bool:
        return self.user is not None and self.user.is_admin

    @property
    def visibility(self) -> Visibility:
        if self.user is None:
            return Visibility()
        return Visibility(
            is_admin=self.user.is_admin, user_id=self.user.id, groups=tuple(self.user.groups)
        )


ANONYMOUS = Principal(user=None)


def may_see_level(principal: Principal, role: str | None, level: str) -> bool:
    if level == "public" or principal.is_admin:
        return True
    if principal.user is None:
        return False
    if level == "private":
        return role in ("owner", "editor")
    return role is not None or level in principal.user.groups


def has_role(principal: Principal, role: str | None, needed: str) -> bool:
    return principal.is_admin or ROLE_RANK.get(role or "", 0) >= ROLE_RANK[needed]
