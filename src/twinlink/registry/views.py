"""The document a reader sees: visible parts merged, relations and timestamps filled in."""

from __future__ import annotations

from typing import Any

from twinlink.domain.merge import level_order, merge_parts
from twinlink.domain.records import Edge, TwinRecord
from twinlink.registry.build import human_time, machine_time

_LEADING = ("version", "privacy", "id", "dt-id", "hosting-iri", "name", "description")
_TIMES = ("createdMachine", "createdHuman", "modifiedMachine", "modifiedHuman")


RelationKey = tuple[str, str]  # (relationType, the other twin's id), seen from this twin


def relation_key(entry: Any) -> RelationKey | None:
    """The key of a relation entry as a document writes it; None for one that is not whole."""
    if not isinstance(entry, dict):
        return None
    kind, other = entry.get("relationType"), entry.get("id") or entry.get("dt-id")
    return (kind, other) if isinstance(kind, str) and isinstance(other, str) else None


def declared_entries(parts: dict[str, dict[str, Any]]) -> dict[RelationKey, dict[str, Any]]:
    """The relation entries the parts write, as written (custom keys too); where several parts
    write the same relation, the most private one's entry, as merging would give."""
    out: dict[RelationKey, dict[str, Any]] = {}
    for level in sorted(parts, key=level_order):
        for entry in parts[level].get("relations") or []:
            key = relation_key(entry)
            if key is not None:
                out[key] = entry
    return out


def relation_entries(
    dt_id: str,
    edges: list[Edge],
    id_key: str,
    declared: dict[RelationKey, dict[str, Any]] | None = None,
) -> list[dict[str, Any]]:
    """One entry per relation of the graph; a relation the twin's own parts write keeps its
    entry as written (`note: ...` and other keys), the others get `relationType` and the id."""
    seen: set[RelationKey] = set()
    out = []
    for e in sorted(edges, key=lambda e: (e.kind, e.source, e.target)):
        if e.kind == "parent":
            entry = ("child", e.target) if e.source == dt_id else ("parent", e.source)
        else:
            entry = ("sibling", e.target if e.source == dt_id else e.source)
        if entry not in seen and entry[1] != dt_id:
            seen.add(entry)
            written = (declared or {}).get(entry)
            out.append(dict(written) if written else {"relationType": entry[0], id_key: entry[1]})
    return out


def render_document(
    twin: TwinRecord, parts: dict[str, dict[str, Any]], edges: list[Edge], canonical_url: str
) -> dict[str, Any]:
    """Merge the visible `parts`; `edges` must already be filtered to what the reader may see."""
    merged = merge_parts(parts)
    id_key = "id" if any("id" in p for p in parts.values()) else "dt-id"
    merged.pop("id", None)
    merged.pop("dt-id", None)
    merged[id_key] = twin.dt_id
    merged.setdefault("hosting-iri", canonical_url)
    times = {
        "createdMachine": machine_time(twin.created_ns),
        "createdHuman": human_time(twin.created_ns),
        "modifiedMachine": machine_time(twin.modified_ns),
        "modifiedHuman": human_time(twin.modified_ns),
    }
    relations = relation_entries(twin.dt_id, edges, id_key, declared_entries(parts))
    out: dict[str, Any] = {k: merged[k] for k in _LEADING if k in merged}
    out.update(times)
    for key, value in merged.items():
        if key == "features" and relations:
            out["relations"] = relations
        if key not in out:
            out[key] = value
    if relations and "relations" not in out:
        out["relations"] = relations
    return out
