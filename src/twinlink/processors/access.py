"""Who may read or change a twin's processors: a viewer of the twin reads them, an editor
changes them."""

from __future__ import annotations

from twinlink.auth.rights import Principal, has_role
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.records import ProcessorRecord, TwinRecord
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore


def raise_forbidden(slug: str) -> None:
    raise ForbiddenError(f"changing processors of {slug!r} needs the editor role")


async def editable_twin(registry: RegistryService, principal: Principal, slug: str) -> TwinRecord:
    twin, role = await registry.require_twin(principal, slug)
    if not has_role(principal, role, "editor"):
        raise_forbidden(slug)
    return twin


async def stored_processor(
    registry: RegistryService,
    store: MetadataStore,
    principal: Principal,
    slug: str,
    name: str,
    needed: str,
) -> ProcessorRecord:
    """The processor `name` of twin `slug` as stored, if `principal` has the `needed` role
    ("viewer" or "editor") on the twin."""
    twin, role = await registry.require_twin(principal, slug)
    if needed == "editor" and not has_role(principal, role, "editor"):
        raise_forbidden(slug)
    for record in await store.list_processors(twin.id):
        if record.name == name:
            return record
    raise NotFoundError(f"twin {slug!r} has no processor {name!r}")
