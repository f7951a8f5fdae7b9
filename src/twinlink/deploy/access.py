"""Who may see and change a deployment: the rights of its twin.

A deployment is seen by whoever may see its twin (while it is live), by who created it, and
by admins; it is changed by the owners of its twin and admins. A deployment the caller may
not see is answered as one that does not exist, as its twin is."""

from __future__ import annotations

from twinlink.auth.rights import Principal, has_role
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import ConflictError, ForbiddenError, NotFoundError
from twinlink.domain.records import User
from twinlink.registry.service import RegistryService


async def may_see(
    registry: RegistryService, principal: Principal, record: DeploymentRecord
) -> bool:
    if principal.is_admin or (principal.user and principal.user.id == record.created_by):
        return True
    try:
        await registry.require_twin(principal, record.twin)
    except NotFoundError:
        return False
    return record.live


async def check_may_change(
    registry: RegistryService,
    principal: Principal,
    record: DeploymentRecord,
    *,
    ended: bool = False,
) -> None:
    """`ended`: a terminated deployment may be changed too (terminated again, to remove what
    a server stopped before it had removed)."""
    if not record.live and not (ended and record.state == "terminated"):
        raise ConflictError(f"deployment {record.name!r} is {record.state}; create it again")
    twin = await registry.get_twin(record.twin)
    role = await registry.role_of(principal, twin) if twin else None
    if not has_role(principal, role, "owner"):
        raise ForbiddenError(
            f"changing deployment {record.name!r} needs the owner role on its twin"
        )


def signed_in(principal: Principal) -> User:
    if principal.user is None:
        raise ForbiddenError("sign in to deploy twin packages")
    return principal.user
