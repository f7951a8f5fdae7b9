"""Service accounts: identities for features that call other features through the gateway
(the Data Link paper's predictive maintenance fetching history and models).

A service account of twin `crane` named `maintenance` is the user `svc-crane-maintenance`: it
has no password (it cannot sign in), holds a role on that twin only, and its token (kind
`service`, no expiry) goes through the very checks every caller's does.
"""

from __future__ import annotations

from typing import Any

from twinlink.auth.rights import Principal, has_role
from twinlink.auth.service import AuthService
from twinlink.domain.errors import ForbiddenError, InvalidInputError, NotFoundError
from twinlink.domain.records import TwinRecord
from twinlink.gateway.spec import check_name
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore

PREFIX = "svc-"


def account_name(slug: str, name: str) -> str:
    return f"{PREFIX}{slug}-{name}"


class ServiceAccounts:
    def __init__(self, auth: AuthService, registry: RegistryService, store: MetadataStore):
        self.auth = auth
        self.registry = registry
        self.store = store

    async def _owned(self, principal: Principal, slug: str) -> TwinRecord:
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "owner"):
            raise ForbiddenError(f"service accounts of {slug!r} need the owner role")
        return twin

    async def list(self, principal: Principal, slug: str) -> list[dict[str, Any]]:
        twin = await self._owned(principal, slug)
        prefix = account_name(slug, "")
        found = []
        for user_id, username, role in await self.store.list_roles(twin.id):
            if username.startswith(prefix):
                found.append(
                    {
                        "name": username[len(prefix) :],
                        "user": username,
                        "role": role,
                        "user_id": user_id,
                    }
                )
        return found

    async def create(self, principal: Principal, slug: str, name: str, role: Any) -> dict[str, Any]:
        await self._owned(principal, slug)
        try:
            check_name(name)
        except ValueError as err:
            raise InvalidInputError(str(err)) from err
        role = role or "viewer"
        if role not in ("viewer", "editor"):
            raise InvalidInputError("a service account's role is viewer or editor")
        username = account_name(slug, name)
        user = await self.auth.create_user(username, None, False, [])
        await self.registry.set_role(principal, slug, username, role)
        issued = await self.auth.issue_token(user, f"service account {name}", None, kind="service")
        return {
            "name": name,
            "user": username,
            "role": role,
            "token": issued.token,
            "token_prefix": issued.record.prefix,
        }

    async def delete(self, principal: Principal, slug: str, name: str) -> None:
        await self._owned(principal, slug)
        username = account_name(slug, name)
        user = await self.store.get_user_by_name(username)
        if user is None:
            raise NotFoundError(f"the twin {slug!r} has no service account {name!r}")
        await self.auth.delete_user(user)
