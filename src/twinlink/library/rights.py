"""Who may read and write which library scope. One place, so the API, resolve and search
apply the same rules.

`common` is read by every signed-in user and written by admins and the curators' group;
`group:g` is read and written by members of g; `user:u` by u alone. Admins may do anything.
A scope the caller may not read is answered as if the asset did not exist (404), so a
private asset's existence does not leak; one they may read but not write is a 403.
"""

from __future__ import annotations

from dataclasses import dataclass

from twinlink.auth.rights import Principal
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.library import COMMON, GROUP_PREFIX, USER_PREFIX


@dataclass(frozen=True, slots=True)
class LibraryRights:
    curators: str = "curators"  # the group that writes `common` (setting library_curators)
    fmu_uploaders: str = "admins"  # setting fmu_uploaders: admins, or whoever may write

    def may_read(self, principal: Principal, scope: str) -> bool:
        user = principal.user
        if user is None:
            return False
        if user.is_admin or scope == COMMON:
            return True
        if scope.startswith(GROUP_PREFIX):
            return scope[len(GROUP_PREFIX) :] in user.groups
        return scope == USER_PREFIX + user.username

    def may_write(self, principal: Principal, scope: str) -> bool:
        user = principal.user
        if user is None:
            return False
        if scope == COMMON:
            return user.is_admin or self.curators in user.groups
        return self.may_read(principal, scope)

    def readable_scopes(self, principal: Principal) -> list[str] | None:
        """The scopes the caller reads, in lookup order (their own, their groups sorted,
        common); None for an admin, who reads every scope."""
        if principal.is_admin:
            return None
        return self.lookup_order(principal)

    def lookup_order(self, principal: Principal) -> list[str]:
        """Where a reference without a scope is looked for, first match wins."""
        user = principal.user
        if user is None:
            return []
        groups = [GROUP_PREFIX + g for g in sorted(user.groups)]
        return [USER_PREFIX + user.username, *groups, COMMON]

    def check_read(self, principal: Principal, scope: str, what: str) -> None:
        if not self.may_read(principal, scope):
            raise NotFoundError(f"the library has no {what}")

    def check_write(self, principal: Principal, scope: str, what: str) -> None:
        self.check_read(principal, scope, what)
        if not self.may_write(principal, scope):
            raise ForbiddenError(
                f"only admins and members of the group {self.curators!r} (library_curators) "
                "change the common library; push to your own space (scope 'me') or a "
                "group's instead"
            )

    def check_fmu_upload(self, principal: Principal, fmus: list[str]) -> None:
        if fmus and self.fmu_uploaders == "admins" and not principal.is_admin:
            raise ForbiddenError(
                f"{fmus[0]} is an FMU: native code that runs on the server, so only admins "
                "push FMUs (TWINLINK_FMU_UPLOADERS=editors lets whoever may write the scope)"
            )
