"""Apply: turn grouped document parts into one atomic write of one or more twins."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

from twinlink.auth.rights import Principal, has_role, may_see_level
from twinlink.domain.document import validate_part
from twinlink.domain.errors import ConflictError, DocumentError, ForbiddenError, NotFoundError
from twinlink.domain.records import Edge, TwinRecord, TwinWrite
from twinlink.domain.slug import SLUG, slug_for
from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.build import declared_edges, imported_created_ns, search_rows
from twinlink.registry.documents import REFUSED, TwinParts
from twinlink.registry.readback import as_stored, is_view_of, refuse_merged_view
from twinlink.store.base import MetadataStore

Outcome = Literal["created", "updated", "unchanged"]
Mode = Literal["apply", "create", "update"]


@dataclass(slots=True)
class Applied:
    twin: TwinRecord
    outcome: Outcome
    levels: list[str]


@dataclass(slots=True)
class _Plan:
    existing: TwinRecord | None
    write: TwinWrite | None  # None: unchanged


class Applier:
    """Plans every twin of a request (rights, conflicts, slugs) before anything is written,
    then writes them all in one transaction; the store refuses composition cycles in it."""

    def __init__(self, store: MetadataStore, canonical_url: Callable[[str], str]) -> None:
        self.store = store
        self.canonical_url = canonical_url

    async def apply(
        self,
        principal: Principal,
        groups: list[TwinParts],
        slug: str | None,
        mode: Mode,
        dry_run: bool = False,
    ) -> list[Applied]:
        reserved: set[str] = set()  # slugs taken by new twins earlier in this request
        plans = [await self._plan(principal, g, slug, mode, reserved) for g in groups]
        if dry_run:
            return [_preview(p) for p in plans]
        return await self.write(plans)

    async def write(self, plans: list[_Plan]) -> list[Applied]:
        records = iter(await self.store.save_twins([p.write for p in plans if p.write]))
        out = []
        for p in plans:
            if p.write is None:
                assert p.existing is not None
                out.append(Applied(p.existing, "unchanged", p.existing.levels))
            else:
                outcome: Outcome = "created" if p.existing is None else "updated"
                out.append(Applied(next(records), outcome, sorted(p.write.parts)))
        return out

    async def _plan(
        self,
        principal: Principal,
        group: TwinParts,
        slug: str | None,
        mode: Mode,
        reserved: set[str],
    ) -> _Plan:
        existing = await self._find(principal, group, slug, mode)
        if existing is not None:
            new_slug = slug or group.explicit_slug or existing.slug
            if new_slug != existing.slug and (
                new_slug in reserved or await self.store.get_twin(new_slug)
            ):
                raise ConflictError(f"cannot rename {existing.slug!r}: {new_slug!r} is taken")
            dt_id = existing.dt_id
            old_parts = await self.store.get_parts(existing.id)
            parts = dict(old_parts)
            created = existing.created_ns
        else:
            part = group.first[0]
            new_slug = slug_for(
                slug or group.explicit_slug, part.hosting_iri, group.global_id, part.name
            )
            if new_slug in reserved or await self.store.get_twin(new_slug) is not None:
                if slug or group.explicit_slug:
                    raise ConflictError(f"the slug {new_slug!r} is asked for twice or taken")
                new_slug = await self._free_slug(new_slug, reserved)
            # Twinbase's `dt-id: autoassign|BASE` names the twin BASE/{slug}.
            base = next((p.id_base for p, _, _ in group.parts.values() if p.id_base), None)
            assigned = f"{base}/{new_slug}" if base else self.canonical_url(new_slug)
            dt_id = group.global_id or assigned
            old_parts = None
            parts = {}
            imported = [imported_created_ns(src.data) for _, _, src in group.parts.values()]
            created = next((c for c in imported if c is not None), time.time_ns())
        if not SLUG.match(new_slug):
            raise DocumentError(
                REFUSED,
                [
                    group.first[2].problem(
                        f"slug {new_slug!r} must be 1-64 lowercase letters, digits and dashes",
                        ("slug",),
                    )
                ],
            )
        reserved.add(new_slug)
        unchanged: set[str] = set()
        if existing is not None and old_parts is not None:
            unchanged = await self._unchanged_levels(existing, group, old_parts)
        urls = {self.canonical_url(new_slug)}
        if existing is not None:
            urls.add(self.canonical_url(existing.slug))
        for level, (_, body, _) in group.parts.items():
            if level not in unchanged:
                parts[level] = as_stored(body, dt_id, urls)
        return await self.plan_write(
            principal, existing, new_slug, dt_id, parts, created, old_parts
        )

    async def _unchanged_levels(
        self, twin: TwinRecord, group: TwinParts, stored: dict[str, dict[str, Any]]
    ) -> set[str]:
        """The levels whose stored part stays: the document equals it, or is a view of the twin
        read back (GET then apply). A changed merged view is refused (see `readback`)."""
        edges: list[Edge] | None = None
        canonical = self.canonical_url(twin.slug)
        unchanged = set()
        for level, (_, body, source) in group.parts.items():
            kept = stored.get(level)
            if body == kept:
                unchanged.add(level)
                continue
            if kept is not None:
                if edges is None:
                    edges = await self.store.edges_touching([twin.dt_id])
                if is_view_of(body, level, stored, twin, canonical, edges):
                    unchanged.add(level)
                    continue
            refuse_merged_view(source, level, stored, twin.slug)
        return unchanged

    async def plan_write(
        self,
        principal: Principal,
        existing: TwinRecord | None,
        slug: str,
        dt_id: str,
        parts: dict[str, dict[str, Any]],
        created_ns: int,
        old_parts: dict[str, dict[str, Any]] | None = None,
    ) -> _Plan:
        """What writing `parts` would change; nothing when they equal `old_parts` (the edges a
        twin declares follow from its parts, so equal parts declare equal edges)."""
        if existing is not None and existing.slug == slug and old_parts == parts:
            return _Plan(existing, None)
        models = {level: validate_part(SourceDocument(body))[0] for level, body in parts.items()}
        edges = declared_edges(dt_id, models)
        write = TwinWrite(
            slug=slug,
            dt_id=dt_id,
            # Listings show the public part's name only, so a private name never leaks; a twin
            # without a named public part is listed by its slug.
            name=_public_name(parts) or slug,
            created_ns=created_ns,
            modified_ns=time.time_ns(),
            parts=parts,
            edges=edges,
            search_rows=search_rows(parts),
            owner_user_id=principal.user.id if existing is None and principal.user else None,
            twin_id=existing.id if existing else None,
        )
        return _Plan(existing, write)

    async def _find(
        self, principal: Principal, group: TwinParts, slug: str | None, mode: Mode
    ) -> TwinRecord | None:
        dt_id = group.global_id
        explicit = slug or group.explicit_slug
        existing = await self.store.get_twin_by_dt_id(dt_id) if dt_id else None
        if existing is None and explicit:
            existing = await self.store.get_twin(explicit)
            if existing is not None and dt_id and existing.dt_id != dt_id:
                raise ConflictError(f"the slug {explicit!r} belongs to another twin")
        if existing is None and not dt_id:
            part = group.first[0]
            existing = await self.store.get_twin(
                slug_for(explicit, part.hosting_iri, None, part.name)
            )
        if existing is not None:
            await self._may_change(principal, existing, mode, slug)
        if mode == "create" and existing is not None:
            raise ConflictError(
                f"the twin {existing.slug!r} already exists; use apply or PUT to change it"
            )
        if mode == "update" and existing is None:
            raise NotFoundError(f"no twin {slug!r}")
        if existing is not None and slug is not None and existing.slug != slug:
            raise ConflictError(f"the document's id belongs to another twin than {slug!r}")
        return existing

    async def _may_change(
        self, principal: Principal, twin: TwinRecord, mode: Mode, slug: str | None
    ) -> None:
        """Editors may change a twin. A twin the caller may not see stays hidden: addressed by
        slug it does not exist (404); addressed by id, the id is taken, which cannot be
        hidden, but its slug and content are not named."""
        assert principal.user is not None
        role = await self.store.get_role(twin.id, principal.user.id)
        if has_role(principal, role, "editor"):
            return
        if not any(may_see_level(principal, role, level) for level in twin.levels):
            if mode == "update":
                raise NotFoundError(f"no twin {slug!r}")
            raise ForbiddenError("the document names a twin (by id or slug) you may not change")
        raise ForbiddenError(f"changing {twin.slug!r} needs the editor role")

    async def _free_slug(self, base: str, reserved: set[str]) -> str:
        for n in range(2, 10_000):
            candidate = f"{base[:58]}-{n}"
            if candidate not in reserved and await self.store.get_twin(candidate) is None:
                return candidate
        raise ConflictError(f"no free slug near {base!r}")


def _preview(plan: _Plan) -> Applied:
    """What writing `plan` would answer, without writing it (an update's dry run; a composition
    cycle is found only by the write's transaction)."""
    assert plan.existing is not None  # dry runs are for updates only
    if plan.write is None:
        return Applied(plan.existing, "unchanged", plan.existing.levels)
    return Applied(plan.existing, "updated", sorted(plan.write.parts))


def _public_name(parts: dict[str, dict[str, Any]]) -> str:
    name = parts.get("public", {}).get("name")
    return name if isinstance(name, str) else ""
