"""Apply, read, list and delete twins, keeping privacy parts, relations and search in step."""

from __future__ import annotations

import asyncio
import time
from collections import defaultdict
from dataclasses import dataclass
from typing import Any, Literal

import orjson

from twinlink.auth.rights import Principal, has_role, may_see_level
from twinlink.domain.document import DocumentPart, validate_part
from twinlink.domain.errors import ConflictError, DocumentError, NotFoundError, Problem
from twinlink.domain.slug import SLUG, slug_for
from twinlink.domain.yamlsource import SourceDocument, parse_yaml_stream
from twinlink.registry.build import declared_edges, imported_created_ns, search_rows
from twinlink.registry.views import render_document
from twinlink.store.base import MetadataStore
from twinlink.store.records import Edge, TwinRecord, TwinWrite


class ForbiddenError(Exception):
    """A known caller without the right for this action (HTTP 403)."""


Outcome = Literal["created", "updated", "unchanged"]


@dataclass(slots=True)
class Applied:
    twin: TwinRecord
    outcome: Outcome
    levels: list[str]


@dataclass(slots=True)
class _Group:
    """The parts of one twin found in one request."""

    key: str
    parts: dict[str, tuple[DocumentPart, dict[str, Any], SourceDocument]]


def parse_documents(body: bytes, content_type: str, max_bytes: int) -> list[SourceDocument]:
    """YAML (one or many documents) or JSON (an object or a list of objects)."""
    if len(body) > max_bytes:
        raise DocumentError(
            f"The document is {len(body)} bytes; the limit is {max_bytes}"
            " (TWINLINK_MAX_DOCUMENT_BYTES)."
        )
    try:
        text = body.decode("utf-8")
    except UnicodeDecodeError as err:
        raise DocumentError("The document is not UTF-8 text.", [Problem(str(err))]) from err
    if "json" in content_type:
        try:
            data = orjson.loads(body)
        except orjson.JSONDecodeError as err:
            raise DocumentError(
                "The document is not valid JSON; nothing was stored.",
                [Problem(err.msg, line=err.lineno, column=err.colno)],
            ) from err
        items = data if isinstance(data, list) else [data]
        try:
            # JSON is YAML: parsing it again gives the line and column of every value.
            marked = parse_yaml_stream(text)[0]
            marks = marked.marks if isinstance(data, dict) else {}
        except (DocumentError, IndexError):
            marks = {}
        return [
            SourceDocument(item, marks if len(items) == 1 else {}, i)
            for i, item in enumerate(items)
        ]
    docs = parse_yaml_stream(text)
    if not docs:
        raise DocumentError(
            "The request holds no document.", [Problem("empty body", line=1, column=1)]
        )
    return docs


class RegistryService:
    def __init__(self, store: MetadataStore, base_url: str) -> None:
        self.store = store
        self.base_url = base_url.rstrip("/")
        # Applies check the relation graph and then write it; one at a time keeps that sound.
        self._write_lock = asyncio.Lock()

    def canonical_url(self, slug: str) -> str:
        return f"{self.base_url}/twins/{slug}"

    # -- apply ---------------------------------------------------------------------------

    async def apply(
        self,
        principal: Principal,
        docs: list[SourceDocument],
        *,
        slug: str | None = None,
        mode: Literal["apply", "create", "update"] = "apply",
    ) -> list[Applied]:
        """Validate every document first (nothing is written if any has a problem), then write
        each twin in its own transaction."""
        if principal.user is None:
            raise ForbiddenError("sign in to change twins")
        groups = self._group(docs, slug)
        results = []
        async with self._write_lock:
            reserved: set[str] = set()  # slugs taken by new twins earlier in this request
            plans = [await self._plan(principal, g, slug, mode, reserved) for g in groups]
            for plan in plans:
                results.append(await self._write(principal, *plan))
        return results

    def _group(self, docs: list[SourceDocument], slug: str | None) -> list[_Group]:
        problems: list[Problem] = []
        groups: dict[str, _Group] = {}
        for source in docs:
            try:
                part, raw = validate_part(source)
            except DocumentError as err:
                problems.extend(err.problems)
                continue
            key = (
                part.global_id
                or slug
                or raw.get("slug")
                or slug_for(None, part.hosting_iri, None, part.name)
            )
            if not key:
                problems.append(
                    source.problem(
                        "the twin has no `id`/`dt-id` and no name to derive its slug from"
                    )
                )
                continue
            group = groups.setdefault(str(key), _Group(str(key), {}))
            if part.privacy in group.parts:
                problems.append(
                    source.problem(
                        f"a second {part.privacy!r} part for the same twin in one request",
                        ("privacy",),
                    )
                )
                continue
            group.parts[part.privacy] = (part, raw, source)
        if problems:
            raise DocumentError("The DT document has problems; nothing was stored.", problems)
        if slug is not None and len(groups) > 1:
            raise DocumentError("A request for one twin holds documents of several twins.")
        return list(groups.values())

    async def _plan(
        self,
        principal: Principal,
        group: _Group,
        slug: str | None,
        mode: str,
        reserved: set[str],
    ) -> tuple[
        TwinRecord | None, str, str, dict[str, dict[str, Any]], dict[str, DocumentPart], int
    ]:
        first = next(iter(group.parts.values()))
        part, _, source = first
        dt_id = next((p.global_id for p, _, _ in group.parts.values() if p.global_id), None)
        explicit = slug or next(
            (r.get("slug") for _, r, _ in group.parts.values() if r.get("slug")), None
        )
        existing = await self.store.get_twin_by_dt_id(dt_id) if dt_id else None
        if existing is None and explicit:
            existing = await self.store.get_twin(str(explicit))
            if existing is not None and dt_id and existing.dt_id != dt_id:
                raise ConflictError(
                    f"the slug {explicit!r} belongs to another twin ({existing.dt_id})"
                )
        if existing is None and not dt_id:
            candidate = slug_for(explicit, part.hosting_iri, None, part.name)
            existing = await self.store.get_twin(candidate)
        if mode == "create" and existing is not None:
            raise ConflictError(
                f"the twin {existing.slug!r} already exists; use apply or PUT to change it"
            )
        if mode == "update" and existing is None:
            raise NotFoundError(f"no twin {slug!r}")
        if existing is not None and slug is not None and existing.slug != slug:
            raise ConflictError(
                f"the document's id {dt_id!r} belongs to the twin {existing.slug!r}, not {slug!r}"
            )

        if existing is not None:
            role = await self.store.get_role(existing.id, principal.user.id)  # type: ignore[union-attr]
            if not has_role(principal, role, "editor"):
                raise ForbiddenError(f"changing {existing.slug!r} needs the editor role")
            new_slug = existing.slug if not explicit else str(explicit)
            if new_slug != existing.slug and (
                new_slug in reserved or await self.store.get_twin(new_slug) is not None
            ):
                raise ConflictError(f"cannot rename {existing.slug!r}: {new_slug!r} is taken")
            dt_id = dt_id or existing.dt_id
            parts = await self.store.get_parts(existing.id)
            created = existing.created_ns
        else:
            new_slug = slug_for(explicit, part.hosting_iri, dt_id, part.name)
            if new_slug in reserved or await self.store.get_twin(new_slug) is not None:
                new_slug = await self._free_slug(new_slug, reserved)
            dt_id = dt_id or self.canonical_url(new_slug)
            parts = {}
            imported = [imported_created_ns(src.data) for _, _, src in group.parts.values()]
            created = next((c for c in imported if c is not None), time.time_ns())
        if not SLUG.match(new_slug):
            raise DocumentError(
                "The document has problems; nothing was stored.",
                [
                    source.problem(
                        f"slug {new_slug!r} must be 1-64 lowercase letters, digits and dashes",
                        ("slug",),
                    )
                ],
            )
        for level, (_, body, _) in group.parts.items():
            parts[level] = body
        models = {level: validate_part(SourceDocument(body))[0] for level, body in parts.items()}
        reserved.add(new_slug)
        return existing, new_slug, dt_id, parts, models, created

    async def _free_slug(self, base: str, reserved: set[str]) -> str:
        for n in range(2, 10_000):
            candidate = f"{base[:58]}-{n}"
            if candidate not in reserved and await self.store.get_twin(candidate) is None:
                return candidate
        raise ConflictError(f"no free slug near {base!r}")

    async def _write(
        self,
        principal: Principal,
        existing: TwinRecord | None,
        slug: str,
        dt_id: str,
        parts: dict[str, dict[str, Any]],
        models: dict[str, DocumentPart],
        created_ns: int,
    ) -> Applied:
        edges = declared_edges(dt_id, models)
        await self._refuse_cycles(dt_id, edges)
        if existing is not None:
            old_parts = await self.store.get_parts(existing.id)
            old_edges = [
                e for e in await self.store.edges_touching([dt_id]) if e.declared_by == dt_id
            ]
            if (
                old_parts == parts
                and existing.slug == slug
                and _edge_keys(old_edges) == _edge_keys(edges)
            ):
                return Applied(existing, "unchanged", sorted(parts))
        # The spec's split documents name the twin in one part only (usually the public one);
        # until that part arrives, the slug stands in for the name.
        name = _public_name(parts) or slug
        record = await self.store.save_twin(
            TwinWrite(
                slug=slug,
                dt_id=dt_id,
                name=name,
                created_ns=created_ns,
                modified_ns=time.time_ns(),
                parts=parts,
                edges=edges,
                search_rows=search_rows(parts),
                owner_user_id=principal.user.id if existing is None and principal.user else None,
                twin_id=existing.id if existing else None,
            )
        )
        return Applied(record, "created" if existing is None else "updated", sorted(parts))

    async def _refuse_cycles(self, dt_id: str, declared: list[Edge]) -> None:
        others = [e for e in await self.store.edges_touching([dt_id]) if e.declared_by != dt_id]
        parents = {
            e.source for e in [*others, *declared] if e.kind == "parent" and e.target == dt_id
        }
        children = {
            e.target for e in [*others, *declared] if e.kind == "parent" and e.source == dt_id
        }
        if dt_id in parents | children:
            raise ConflictError("a twin cannot be its own parent or child")
        loop = parents & (
            await self.store.descendants(children, exclude=dt_id) if children else set()
        )
        if loop:
            raise ConflictError(
                f"the relations would make a composition cycle: {sorted(loop)[0]} would be both "
                f"an ancestor and a descendant of {dt_id}"
            )

    # -- read ----------------------------------------------------------------------------

    async def role_of(self, principal: Principal, twin: TwinRecord) -> str | None:
        if principal.user is None:
            return None
        return await self.store.get_role(twin.id, principal.user.id)

    async def require_twin(self, principal: Principal, slug: str) -> tuple[TwinRecord, str | None]:
        """The twin, if the caller may see any part of it; otherwise NotFoundError (a twin the
        caller may not see is not admitted to exist)."""
        twin = await self.store.get_twin(slug)
        if twin is None:
            raise NotFoundError(f"no twin {slug!r}")
        role = await self.role_of(principal, twin)
        if not any(may_see_level(principal, role, level) for level in twin.levels):
            raise NotFoundError(f"no twin {slug!r}")
        return twin, role

    async def document(self, principal: Principal, slug: str) -> tuple[TwinRecord, dict[str, Any]]:
        twin, role = await self.require_twin(principal, slug)
        parts = {
            k: v
            for k, v in (await self.store.get_parts(twin.id)).items()
            if may_see_level(principal, role, k)
        }
        edges = [
            e
            for e in await self.store.edges_touching([twin.dt_id])
            if may_see_level(principal, role, e.privacy)
        ]
        return twin, render_document(twin, parts, edges, self.canonical_url(twin.slug))

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
            models = {k: validate_part(SourceDocument(v))[0] for k, v in parts.items()}
            return (
                await self._write(
                    principal, twin, twin.slug, twin.dt_id, parts, models, twin.created_ns
                )
            ).twin

    # -- delete --------------------------------------------------------------------------

    async def delete(self, principal: Principal, slug: str, cascade: bool) -> list[str]:
        async with self._write_lock:
            twin, role = await self.require_twin(principal, slug)
            if not has_role(principal, role, "owner"):
                raise ForbiddenError(f"deleting {slug!r} needs the owner role")
            doomed = [twin]
            descendants = await self.store.descendants(
                [
                    e.target
                    for e in await self.store.edges_touching([twin.dt_id])
                    if e.kind == "parent" and e.source == twin.dt_id
                ],
                exclude=twin.dt_id,
            )
            registered = await self.store.get_twins_by_dt_ids(descendants)
            if registered and not cascade:
                names = ", ".join(sorted(t.slug for t in registered.values()))
                raise ConflictError(
                    f"{slug!r} has children ({names}); delete them first or ask for cascade=true"
                )
            for child in registered.values():
                child_role = await self.role_of(principal, child)
                if not has_role(principal, child_role, "owner"):
                    raise ForbiddenError(
                        f"deleting {child.slug!r} (a descendant) needs the owner role"
                    )
                doomed.append(child)
            await self.store.delete_twins(doomed)
            return [t.slug for t in doomed]

    # -- relations -----------------------------------------------------------------------

    async def traverse(
        self, principal: Principal, slug: str, direction: Literal["down", "up"], depth: int
    ) -> dict[str, Any]:
        """The subtree (down) or the ancestors (up) of a twin, to `depth` levels."""
        twin, _ = await self.require_twin(principal, slug)
        root: dict[str, Any] = {"id": twin.dt_id, "slug": twin.slug, "name": twin.name, "nodes": []}
        frontier = {twin.dt_id: root}
        seen = {twin.dt_id}
        for _ in range(depth):
            edges = await self.store.edges_touching(frontier)
            found: dict[str, list[str]] = defaultdict(list)
            for e in edges:
                if e.kind != "parent":
                    continue
                near, far = (e.source, e.target) if direction == "down" else (e.target, e.source)
                if near in frontier and far not in seen:
                    found[near].append(far)
            twins = await self.store.get_twins_by_dt_ids(x for xs in found.values() for x in xs)
            nxt: dict[str, dict[str, Any]] = {}
            for near, fars in found.items():
                for far in dict.fromkeys(fars):
                    node = await self._node(principal, far, twins.get(far))
                    if node is None:
                        continue
                    seen.add(far)
                    frontier[near]["nodes"].append(node)
                    nxt[far] = node
            if not nxt:
                break
            frontier = nxt
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


def _edge_keys(edges: list[Edge]) -> set[tuple[str, str, str, str]]:
    return {(e.source, e.kind, e.target, e.privacy) for e in edges}


def _public_name(parts: dict[str, dict[str, Any]]) -> str:
    from twinlink.domain.merge import level_order

    for level in sorted(parts, key=level_order):
        name = parts[level].get("name")
        if isinstance(name, str) and name:
            return name
    return ""
