"""Making, changing and removing a deployment's resources through the services that own them
(registry, devices, gateway, processors, connectors), so every rule and right of those
services holds for deployments too.

A create writes its journal into the deployment record after each resource is made; when a
step fails, what the journal lists is removed again, last made first. A crash in between
leaves the record in `applying`, and the same undo runs at the next start (service.py).
"""

from __future__ import annotations

import logging
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from pydantic import ValidationError

from twinlink.auth.rights import Principal
from twinlink.connectors.service import ConnectorService
from twinlink.deploy.plan import ORDER, Plan, Resource, canonical, shown
from twinlink.domain.document import validate_part
from twinlink.domain.errors import InvalidInputError, NotFoundError, TwinlinkError
from twinlink.domain.yamlsource import SourceDocument
from twinlink.gateway.service import GatewayService
from twinlink.processors.checks import checked_spec, first_errors
from twinlink.processors.service import ProcessorService
from twinlink.processors.spec import ProcessorSpec
from twinlink.registry.devices import DeviceService
from twinlink.registry.service import RegistryService

log = logging.getLogger("twinlink.deploy")


@dataclass(slots=True)
class Parts:
    """The services a deployment's resources belong to."""

    registry: RegistryService
    devices: DeviceService
    gateway: GatewayService
    processors: ProcessorService
    connectors: ConnectorService
    fingerprint: Callable[[bytes], str]  # the vault's keyed digest

    def entry(self, resource: Resource, hidden: frozenset[str] = frozenset()) -> dict[str, Any]:
        """The journal's entry of a made resource: its spec as shown, and a fingerprint of the
        whole spec (secrets included) to tell a change by."""
        return {
            "type": resource.type,
            "name": resource.name,
            "spec": shown(resource, hidden),
            "fingerprint": self.fingerprint(canonical(resource.spec)),
        }

    def check(self, resource: Resource) -> None:
        """Refuse before anything is made what its service would refuse for its content
        alone: a processor's settings and the twin's document. What depends on the state of
        the platform (a name taken, a right) is found when it is made."""
        where = f"{resource.type} {resource.name!r}"
        try:
            if resource.type == "processor":
                checked_spec(resource.spec, self.processors.catalog)
            elif resource.type == "twin":
                validate_part(SourceDocument(resource.spec))
        except InvalidInputError as err:
            raise InvalidInputError(f"{where}: {err}") from err

    async def make(
        self, principal: Principal, slug: str, resource: Resource, running: bool
    ) -> str | None:
        """Make one resource; a device's token is returned (it cannot be read again)."""
        kind, spec = resource.type, resource.spec
        if kind == "twin":
            docs = [SourceDocument(spec)]
            await self.registry.apply(principal, docs, slug=slug, mode="create")
        elif kind == "device":
            _, token = await self.devices.create(
                principal, slug, resource.name, str(spec.get("description", ""))
            )
            return token
        elif kind == "service":
            body = {k: v for k, v in spec.items() if k != "name"}
            await self.gateway.create(principal, slug, resource.name, body)
        elif kind == "processor":
            await self.processors.create(principal, slug, {**spec, "enabled": running})
        elif kind == "connector":
            await self.connectors.create(principal, slug, {**spec, "enabled": running})
        return None

    async def remove(self, principal: Principal, slug: str, kind: str, name: str) -> None:
        """Remove one resource; one already gone is no error."""
        try:
            if kind == "twin":
                await self.registry.delete(principal, slug, cascade=False)
            elif kind == "device":
                await self.devices.delete(principal, slug, name)
            elif kind == "service":
                await self.gateway.delete(principal, slug, name)
            elif kind == "processor":
                await self.processors.delete(principal, slug, name)
            elif kind == "connector":
                await self.connectors.delete(principal, slug, name)
        except NotFoundError:
            pass

    async def change(
        self, principal: Principal, slug: str, resource: Resource, running: bool
    ) -> None:
        """Change a resource in place where its service can (the twin's document, a
        processor: a running one keeps running, and its state where its blueprint allows);
        a service or connector is made again."""
        if resource.type == "twin":
            docs = [SourceDocument(resource.spec)]
            await self.registry.apply(principal, docs, slug=slug, mode="update")
        elif resource.type == "processor":
            try:
                full = ProcessorSpec.model_validate({**resource.spec, "enabled": running})
            except ValidationError as err:
                raise InvalidInputError(
                    f"processor {resource.name!r}: {first_errors(err)}"
                ) from err
            changes = full.model_dump(mode="json", exclude={"name"})
            await self.processors.update(principal, slug, resource.name, changes)
        elif resource.type in ("service", "connector"):
            await self.remove(principal, slug, resource.type, resource.name)
            await self.make(principal, slug, resource, running)

    async def set_running(
        self, principal: Principal, slug: str, journal: list[dict[str, Any]], running: bool
    ) -> None:
        """Enable (start) or disable (stop) the deployment's processors and connectors."""
        for entry in journal:
            if entry["type"] == "processor":
                await self.processors.set_enabled(principal, slug, entry["name"], running)
            elif entry["type"] == "connector":
                await self.connectors.update(principal, slug, entry["name"], {"enabled": running})

    async def apply_plan(
        self,
        principal: Principal,
        slug: str,
        plan: Plan,
        journal: list[dict[str, Any]],
        running: bool,
        saved: Callable[[], Awaitable[None]],
    ) -> dict[str, str]:
        """Apply a reconfigure's plan to a made deployment: removed resources first (last made
        first), then changed ones in place, then new ones; `journal` follows each step and is
        saved after it. New devices' tokens are returned."""
        tokens: dict[str, str] = {}
        for kind, name in plan.delete:
            await self.remove(principal, slug, kind, name)
            journal[:] = [e for e in journal if (e["type"], e["name"]) != (kind, name)]
            await saved()
        for resource, _ in plan.update:
            await self.change(principal, slug, resource, running)
            journal[:] = [
                self.entry(resource, plan.hidden) if (e["type"], e["name"]) == resource.key else e
                for e in journal
            ]
            await saved()
        for resource in sorted(plan.create, key=lambda r: ORDER.index(r.type)):
            token = await self.make(principal, slug, resource, running)
            journal.append(self.entry(resource, plan.hidden))
            if token is not None:
                tokens[resource.name] = token
            await saved()
        return tokens

    async def undo(
        self,
        principal: Principal,
        slug: str,
        journal: list[dict[str, Any]],
        saved: Callable[[], Awaitable[None]],
    ) -> None:
        """Remove what `journal` lists, last made first, each removal saved as it is done; a
        removal that fails is logged and the rest still tried (the twin last: removing it
        takes whatever is left under it)."""
        while journal:
            entry = journal[-1]
            try:
                await self.remove(principal, slug, entry["type"], entry["name"])
            except TwinlinkError as err:
                log.warning(
                    "deployment %s: undoing %s %s failed: %s", slug, entry["type"],
                    entry["name"], err, extra={"event": "deployment_undo_failed"},
                )  # fmt: skip
            journal.pop()
            await saved()
