"""The gateway's registry of services: who may see and change them, and the lookup the proxy
makes on every request (cached, so a forwarded request costs no database read)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from twinlink.auth.rights import Principal, has_role
from twinlink.auth.vault import Vault
from twinlink.domain.errors import ConflictError, ForbiddenError, InvalidInputError, NotFoundError
from twinlink.domain.records import ServiceRecord, TwinRecord
from twinlink.gateway.audit import AuditLog
from twinlink.gateway.health import HealthLoop
from twinlink.gateway.spec import ServiceSettings, check_name, origin
from twinlink.gateway.table import Service, ServiceBuilder
from twinlink.gateway.upstream import Pool
from twinlink.plugins import split_secrets
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore
from twinlink.store.tokens import SharedTokens


class GatewayService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        vault: Vault,
        default_twin: str | None,
        audit_days: float,
        tokens: SharedTokens | None = None,
    ) -> None:
        self.store = store
        self.registry = registry
        # tokens: the upstream tokens the nodes share (None: one node, each keeps its own)
        self.builder = ServiceBuilder(store, vault, tokens)
        self.vault = vault
        self.default_twin = default_twin
        self.pool = Pool()
        self.audit = AuditLog(store, audit_days)
        self.generation = 0  # bumped on every change of a service's settings
        # Called after every change, so other nodes' caches hear of it (cluster.py).
        self.changed_listeners: list[Callable[[], None]] = []
        self._cache: dict[int, tuple[tuple[int, int], dict[str, Service]]] = {}
        self.health = HealthLoop(self)

    async def open(self) -> None:
        self.audit.start()
        self.health.start()

    async def close(self) -> None:
        await self.health.stop()
        await self.audit.stop()
        self.pool.close()

    def cached(self) -> list[tuple[int, dict[str, Service]]]:
        """The services of the twins looked up lately, by twin id."""
        return [(twin_id, entry[1]) for twin_id, entry in self._cache.items()]

    def changed(self) -> None:
        self.generation += 1
        for listener in self.changed_listeners:
            listener()

    # -- the proxy's lookups ---------------------------------------------------------------

    async def services_of(self, twin: TwinRecord) -> dict[str, Service]:
        stamp = (self.registry.generation, self.generation)
        cached = self._cache.get(twin.id)
        if cached is not None and cached[0] == stamp:
            return cached[1]
        services = await self.builder.build(twin)
        self._cache[twin.id] = (stamp, services)
        return services

    async def twin_and_role(self, principal: Principal, slug: str) -> tuple[TwinRecord, str | None]:
        """The twin and the caller's role. As everywhere in the API, a twin the caller may not
        see is not admitted to exist: the same 404 as an unknown slug. One the caller sees
        (its public part) without a role on it is 403: its services need a role."""
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "viewer"):
            raise ForbiddenError(f"using the services of {slug!r} needs a role on that twin")
        return twin, role

    # -- the registry API ------------------------------------------------------------------

    async def list(self, principal: Principal, slug: str) -> list[Service]:
        twin, _ = await self.twin_and_role(principal, slug)
        return list((await self.services_of(twin)).values())

    async def get(self, principal: Principal, slug: str, name: str) -> Service:
        twin, _ = await self.twin_and_role(principal, slug)
        service = (await self.services_of(twin)).get(name)
        if service is None:
            raise NotFoundError(f"the twin {slug!r} has no service {name!r}")
        return service

    async def require_owner(self, principal: Principal, slug: str) -> TwinRecord:
        twin, role = await self.twin_and_role(principal, slug)
        if not has_role(principal, role, "owner"):
            raise ForbiddenError(
                f"setting up the services of {slug!r} (and their credentials) needs the owner role"
            )
        return twin

    async def create(
        self, principal: Principal, slug: str, name: str, body: dict[str, Any]
    ) -> Service:
        twin = await self.require_owner(principal, slug)
        try:
            check_name(name)
        except ValueError as err:
            raise InvalidInputError(str(err)) from err
        settings = _validated(body)
        if settings.base_url is None:
            raise InvalidInputError("a service added by API needs a `base_url`")
        services = await self.services_of(twin)
        if name in services:
            raise ConflictError(
                f"the twin {slug!r} already has a service {name!r}"
                + (" (from its DT document)" if services[name].source == "document" else "")
            )
        await self._save(twin, name, "api", settings, None, principal, create=True)
        return await self.get(principal, slug, name)

    async def update(
        self, principal: Principal, slug: str, name: str, patch: dict[str, Any]
    ) -> Service:
        twin = await self.require_owner(principal, slug)
        service = (await self.services_of(twin)).get(name)
        if service is None:
            raise NotFoundError(f"the twin {slug!r} has no service {name!r}")
        if service.source == "document" and "base_url" in patch:
            raise InvalidInputError(
                "this service's URL is the feature's apiAddress in the twin's DT document; "
                "change it there"
            )
        record = service.record
        current = dict(record.settings) if record is not None else {}
        kept = self._kept_secrets(service, patch)
        merged = {**current, **patch}
        merged.pop("secret_keys", None)
        if "limits" in patch and isinstance(patch["limits"], dict):
            merged["limits"] = {**current.get("limits", {}), **patch["limits"]}
        if "auth" in patch and isinstance(patch["auth"], dict):
            merged["auth"] = {**kept, **patch["auth"]}
        elif kept:
            merged["auth"] = {**current.get("auth", {}), **kept}
        settings = _validated(merged)
        # A document service's credentials stay tied to the origin they were set for until
        # an owner sets `auth` again: a change of another setting must not unblock a service
        # whose apiAddress was moved by whoever may edit the document.
        keep_origin = service.source == "document" and "auth" not in patch
        await self._save(
            twin, name, service.source, settings, record, principal, False, keep_origin
        )
        return await self.get(principal, slug, name)

    def _kept_secrets(self, service: Service, patch: dict[str, Any]) -> dict[str, Any]:
        """The stored secret fields a patch keeps: all of them when it leaves `auth` alone,
        those it omits when it keeps the same method."""
        record = service.record
        if record is None or record.secret is None:
            return {}
        stored = self.vault.unseal(record.secret)
        new_auth = patch.get("auth")
        if new_auth is None:
            return stored
        if not isinstance(new_auth, dict) or new_auth.get("method") != service.settings.auth.method:
            return {}
        return {k: v for k, v in stored.items() if k not in new_auth}

    async def _save(
        self,
        twin: TwinRecord,
        name: str,
        source: str,
        settings: ServiceSettings,
        record: ServiceRecord | None,
        principal: Principal,
        create: bool,
        keep_origin: bool = False,
    ) -> None:
        public, secret = split_secrets(settings.auth)
        stored = settings.model_dump(by_alias=True, exclude={"auth"})
        if source == "document":
            stored.pop("base_url", None)
        stored["auth"] = public
        stored["secret_keys"] = sorted(secret)
        services = await self.services_of(twin)
        base_url = settings.base_url or (services[name].base_url if name in services else None)
        auth_origin = origin(base_url) if base_url and settings.auth.method != "none" else None
        if keep_origin and record is not None and settings.auth.method != "none":
            auth_origin = record.auth_origin
        now = time.time_ns()
        new = ServiceRecord(
            id=0,
            twin_id=twin.id,
            name=name,
            source=source,
            settings=stored,
            secret=self.vault.seal(secret) if secret else None,
            auth_origin=auth_origin,
            created_by=principal.user.id if principal.user else None,
            created_ns=now,
            modified_ns=now,
        )
        await self.store.put_service(new, create=create or record is None)
        self.builder.forget(twin.id, name)
        self.changed()

    async def delete(self, principal: Principal, slug: str, name: str) -> str:
        """Remove an API service, or reset a document service's settings; says which."""
        twin = await self.require_owner(principal, slug)
        service = (await self.services_of(twin)).get(name)
        if service is None:
            raise NotFoundError(f"the twin {slug!r} has no service {name!r}")
        await self.store.delete_service(twin.id, name)
        self.builder.forget(twin.id, name)
        self.changed()
        if service.source == "document" and service.feature is not None:
            return "reset"  # the feature still lists it: it stays, with default settings
        return "deleted"


def _validated(body: dict[str, Any]) -> ServiceSettings:
    try:
        return ServiceSettings.model_validate(body)
    except ValueError as err:
        # from None: pydantic's error repeats the values, the service's credentials among them.
        raise InvalidInputError(_first_error(err)) from None


def _first_error(err: ValueError) -> str:
    errors = getattr(err, "errors", None)
    if callable(errors):
        first = errors(include_url=False, include_input=False)[0]
        where = ".".join(str(x) for x in first["loc"])
        return f"{where}: {first['msg']}" if where else str(first["msg"])
    return str(err)


__all__ = ["GatewayService"]
