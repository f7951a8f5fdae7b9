"""The registry's entry points: apply, read, list, delete, roles and relations, with the rights
checks that go with each.

Twins by slug and roles by (twin, user) are cached (`GenerationCache`) until the next change:
every write here bumps `generation` once it is done, and so do the other services whose changes
derived data depends on (`changed()`).
"""

from __future__ import annotations

import asyncio
from collections import defaultdict
from collections.abc import Callable
from typing import Any, Literal

from twinlink.auth.rights import Principal, has_role, may_see_level
from twinlink.domain.errors import ConflictError, ForbiddenError, NotFoundError
from twinlink.domain.records import Edge, TwinRecord, User
from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.apply import Applied, Applier, Mode
from twinlink.registry.cache import GenerationCache
from twinlink.registry.documents import group_by_twin
from twinlink.registry.views import render_document
from twinlink.store.base import MetadataStore

__all__ = ["Applied", "RegistryService"]


class RegistryService:
    def __init__(self, store: MetadataStore, base_url: str) -> None:
        self.store = store
        self.base_url = base_url.rstrip("/")
        self.applier = Applier(store, self.canonical_url)
        # Plans read the registry and the write then relies on what they read; one change at
        # a time in this process keeps that sound (the store refuses cycles on its own too).
        self._write_lock = asyncio.Lock()
        # Bumped after every change, so caches of derived data (twins and roles here, ingest's
        # interface rules, the devices commands go to) can tell they are stale without a query.
        self.generation = 0
        # Called with the ids of deleted twins, so other stores can drop what they hold.
        self.deleted_listeners: list[Callable[[list[int]], None]] = []
        # Called after every change, so other nodes' caches hear of it (cluster.py).
        self.changed_listeners: list[Callable[[], None]] = []
        self._twins: GenerationCache[str, TwinRecord] = GenerationCache(self._generation)
        # Keyed by the user's creation time too: a deleted user's id may be given again.
        # No role is cached as "".
        self._roles: GenerationCache[tuple[int, int, int], str] = GenerationCache(self._generation)

    def _generation(self) -> int:
        return self.generation

    def changed(self) -> None:
        """Something twins, roles or devices depend on has changed (call it after the write):
        every cache of derived data starts again."""
        self.generation += 1
        for listener in self.changed_listeners:
            listener()

    def canonical_url(self, slug: str) -> str:
        return f"{self.base_url}/twins/{slug}"

    async def apply(
        self,
        principal: Principal,
        docs: list[SourceDocument],
        *,
        slug: str | None = None,
        mode: Mode = "apply",
        dry_run: bool = False,
    ) -> list[Applied]:
        """Validate every document, plan every twin, then write them all in one transaction:
        a request is stored whole or not at all. `dry_run` (updates only) stops before the
        write and answers what it would have done."""
        if principal.user is None:
            raise ForbiddenError("sign in to change twins")
        groups = group_by_twin(docs, slug)
        async with self._write_lock:
            try:
                return await self.applier.apply(principal, groups, slug, mode, dry_run)
            finally:
                if not dry_run:
                    self.changed()

    # -- read ----------------------------------------------------------------------------

    async def role_of(self, principal: Principal, twin: TwinRecord) -> str | None:
        user = principal.user
        if user is None:
            return None
        key = (twin.id, user.id, user.created_ns)
        role = self._roles.get(key)
        if role is None:
            read_at = self._roles.generation()
            role = await self.store.get_role(twin.id, user.id) or ""
            self._roles.keep(key, role, read_at)
        return role or None

    async def get_twin(self, slug: str) -> TwinRecord | None:
        """The twin of `slug`, or None; no rights checked. Records are shared: do not change
        them."""
        twin = self._twins.get(slug)
        if twin is None:
            read_at = self._twins.generation()
            twin = await self.store.get_twin(slug)
            if twin is not None:  # unknown slugs are not kept: anyone may ask for any number
                self._twins.keep(slug, twin, read_at)
        return twin

    async def require_twin(self, principal: Principal, slug: str) -> tuple[TwinRecord, str | None]:
        """The twin, if the caller may see any part of it; otherwise NotFoundError (a twin the
        caller may not see is not admitted to exist)."""
        twin = await self.get_twin(slug)
        if twin is None:
            raise NotFoundError(f"no twin {slug!r}")
        role = await self.role_of(principal, twin)
        if not any(may_see_level(principal, role, level) for level in twin.levels):
            raise NotFoundError(f"no twin {slug!r}")
        return twin, role

    async def require_role(
        self, principal: Principal, slug: str, needed: str, what: str
    ) -> TwinRecord:
        """The twin, if the caller has at least the `needed` role on it (admins always);
        ForbiddenError names `what` the role is needed for. A twin's data (history, live
        streams, commands) needs a role: seeing its public document is not enough."""
        twin, role = await self.require_twin(principal, slug)
        if not has_role(principal, role, needed):
            raise ForbiddenError(f"{what} of {slug!r} need the {needed} role")
        return twin

    async def document(
        self, principal: Principal, slug: str
    ) -> tuple[TwinRecord, str | None, dict[str, Any]]:
        """The twin, the caller's role on it, and the document as the caller may see it."""
        twin, role = await self.require_twin(principal, slug)
        parts = {
            k: v
            for k, v in (await self.store.get_parts(twin.id)).items()
            if may_see_level(principal, role, k)
        }
        edges = await self.visible_edges(principal, await self.store.edges_touching([twin.dt_id]))
        return twin, role, render_document(twin, parts, edges, self.canonical_url(twin.slug))

    async def visible_edges(self, principal: Principal, edges: list[Edge]) -> list[Edge]:
        """Edges whose declaring part the caller may see (a relation declared in a twin's
        private part is as private as the rest of that part)."""
        if principal.is_admin:
            return edges
        hidden = {e.declared_by for e in edges if e.privacy != "public"}
        declarers = await self.store.get_twins_by_dt_ids(hidden)
        roles = {d: await self.role_of(principal, t) for d, t in declarers.items()}
        return [
            e
            for e in edges
            if e.privacy == "public"
            or (
                e.declared_by in declarers
                and may_see_level(principal, roles[e.declared_by], e.privacy)
            )
        ]

    async def part(self, principal: Principal, slug: str, level: str) -> dict[str, Any]:
        twin, role = await self.require_twin(principal, slug)
        parts = await self.store.get_parts(twin.id)
        if level not in parts or not may_see_level(principal, role, level):
            raise NotFoundError(f"twin {slug!r} has no {level!r} part")
        return parts[level]

    async def delete_part(self, principal: Principal, slug: str, level: str) -> TwinRecord:
        async with self._write_lock:
            twin, role = await self.require_twin(principal, slug)
            if not has_role(principal, role, "editor"):
                raise ForbiddenError(f"changing {slug!r} needs the editor role")
            parts = await self.store.get_parts(twin.id)
            if level not in parts or not may_see_level(principal, role, level):
                raise NotFoundError(f"twin {slug!r} has no {level!r} part")
            if len(parts) == 1:
                raise ConflictError("the last part of a twin cannot be removed; delete the twin")
            del parts[level]
            plan = await self.applier.plan_write(
                principal, twin, twin.slug, twin.dt_id, parts, twin.created_ns
            )
            self.changed()
            try:
                return (await self.applier.write([plan]))[0].twin
            finally:
                self.changed()

    # -- delete --------------------------------------------------------------------------

    async def delete(self, principal: Principal, slug: str, cascade: bool) -> list[str]:
        async with self._write_lock:
            twin, role = await self.require_twin(principal, slug)
            if not has_role(principal, role, "owner"):
                raise ForbiddenError(f"deleting {slug!r} needs the owner role")
            children = [
                e.target
                for e in await self.store.edges_touching([twin.dt_id])
                if e.kind == "parent" and e.source == twin.dt_id
            ]
            descendants = await self.store.descendants(children, exclude=twin.dt_id)
            registered = await self.store.get_twins_by_dt_ids(descendants)
            if registered and not cascade:
                names = ", ".join(sorted(t.slug for t in registered.values()))
                raise ConflictError(
                    f"{slug!r} has children ({names}); delete them first or ask for cascade=true"
                )
            doomed = [twin]
            for child in registered.values():
                if not has_role(principal, await self.role_of(principal, child), "owner"):
                    raise ForbiddenError(
                        f"deleting {child.slug!r} (a descendant) needs the owner role"
                    )
                doomed.append(child)
            self.changed()
            try:
                await self.store.delete_twins(doomed)
            finally:
                self.changed()
            for listener in self.deleted_listeners:
                listener([t.id for t in doomed])
            return [t.slug for t in doomed]

    # -- roles ---------------------------------------------------------------------------

    async def set_role(
        self, principal: Principal, slug: str, username: str, role: str | None
    ) -> None:
        """Grant `role` on the twin to `username`, or take their role away (None); owners and
        admins only. The last owner keeps the role until another is granted it."""
        async with self._write_lock:
            twin, own = await self.require_twin(principal, slug)
            if not has_role(principal, own, "owner"):
                raise ForbiddenError(f"granting roles on {slug!r} needs the owner role")
            user = await self._user(username)
            owners = [uid for uid, _, r in await self.store.list_roles(twin.id) if r == "owner"]
            if owners == [user.id] and role != "owner":
                raise ConflictError(
                    f"{twin.slug!r} would have no owner left; grant another owner first"
                )
            try:
                await self.store.set_role(twin.id, user.id, role)
            finally:
                self.changed()

    async def _user(self, username: str) -> User:
        user = await self.store.get_user_by_name(username)
        if user is None:
            raise NotFoundError(f"no user named {username!r}")
        return user

    # -- relations -----------------------------------------------------------------------

    async def traverse(
        self, principal: Principal, slug: str, direction: Literal["down", "up"], depth: int
    ) -> dict[str, Any]:
        """The subtree (down) or the ancestors (up) of a twin, to `depth` levels, through the
        relations and twins the caller may see."""
        twin, _ = await self.require_twin(principal, slug)
        root: dict[str, Any] = {"id": twin.dt_id, "slug": twin.slug, "name": twin.name, "nodes": []}
        frontier = {twin.dt_id: root}
        seen = {twin.dt_id}
        for _ in range(depth):
            edges = await self.visible_edges(principal, await self.store.edges_touching(frontier))
            found: dict[str, list[str]] = defaultdict(list)
            for e in edges:
                near, far = (e.source, e.target) if direction == "down" else (e.target, e.source)
                if e.kind == "parent" and near in frontier and far not in seen:
                    found[near].append(far)
            twins = await self.store.get_twins_by_dt_ids(x for xs in found.values() for x in xs)
            following: dict[str, dict[str, Any]] = {}
            for near, fars in found.items():
                for far in dict.fromkeys(fars):
                    node = await self._node(principal, far, twins.get(far))
                    if node is not None and far not in seen:
                        seen.add(far)
                        frontier[near]["nodes"].append(node)
                        following[far] = node
            if not following:
                break
            frontier = following
        return root

    async def _node(
        self, principal: Principal, dt_id: str, twin: TwinRecord | None
    ) -> dict[str, Any] | None:
        if twin is None:
            return {"id": dt_id, "registered": False, "nodes": []}
        role = await self.role_of(principal, twin)
        if not any(may_see_level(principal, role, level) for level in twin.levels):
            return None
        return {"id": dt_id, "slug": twin.slug, "name": twin.name, "nodes": []}
