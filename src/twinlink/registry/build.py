"""Pure functions that turn validated document parts into what the store keeps."""

from __future__ import annotations

from typing import Any

from twinlink.domain.doctime import TimeRangeError, human_ns, machine_ns
from twinlink.domain.doctime import human_time as human_time  # where the API has it from
from twinlink.domain.document import DocumentPart
from twinlink.domain.merge import level_order
from twinlink.domain.records import Edge, SearchRow

_TWIN_TEXT_KEYS = (
    "id",
    "dt-id",
    "owner",
    "manufacturer",
    "contact",
    "location",
    "hosting-iri",
    "apiGatewayAddress",
)
_NOT_SEARCHED = {
    "version",
    "privacy",
    "name",
    "description",
    "relations",
    "features",
    "interface",
    "slug",
}


def declared_edges(dt_id: str, parts: dict[str, DocumentPart]) -> list[Edge]:
    """The relations the twin's parts declare, as edges of the relation graph."""
    edges: dict[tuple[str, str, str], Edge] = {}
    for level in sorted(parts, key=level_order):
        for rel in parts[level].relations:
            other = rel.target
            if rel.relationType == "parent":
                key = (other, "parent", dt_id)
            elif rel.relationType == "child":
                key = (dt_id, "parent", other)
            else:
                key = (min(dt_id, other), "sibling", max(dt_id, other))
            edges.setdefault(
                key,
                Edge(key[0], "parent" if key[1] == "parent" else "sibling", key[2], dt_id, level),
            )
    return list(edges.values())


def search_rows(parts: dict[str, dict[str, Any]]) -> list[SearchRow]:
    """One row for the twin's own fields and one per feature, for every privacy part."""
    rows = []
    for level, doc in parts.items():
        extra = [_text(doc.get(k)) for k in _TWIN_TEXT_KEYS]
        extra += [
            _text(v) for k, v in doc.items() if k not in _NOT_SEARCHED and k not in _TWIN_TEXT_KEYS
        ]
        interface = doc.get("interface")
        if isinstance(interface, dict):
            extra.append(_text(interface))
        rows.append(
            SearchRow(
                privacy=level,
                feature=None,
                name=_text(doc.get("name")),
                description=_text(doc.get("description")),
                keywords=[],
                extra=" ".join(x for x in extra if x),
            )
        )
        for feature in doc.get("features") or []:
            if not isinstance(feature, dict):
                continue
            keywords = feature.get("keywords") or []
            if isinstance(keywords, str):
                keywords = [keywords]
            custom = [
                _text(v) for k, v in feature.items() if k not in ("name", "description", "keywords")
            ]
            rows.append(
                SearchRow(
                    privacy=level,
                    feature=str(feature.get("name")),
                    name=str(feature.get("name")),
                    description=_text(feature.get("description")),
                    keywords=[str(k) for k in keywords],
                    extra=" ".join(x for x in custom if x),
                )
            )
    return rows


def _text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, dict):
        return " ".join(_text(v) for v in value.values())
    if isinstance(value, list):
        return " ".join(_text(v) for v in value)
    return str(value)


def machine_time(ns: int) -> str:
    return str(ns // 1_000_000_000)


def human_time_or_none(ns: int | None) -> str | None:
    return None if ns is None else human_time(ns)


def imported_created_ns(raw: dict[str, Any]) -> int | None:
    """The creation time a document brings with it (`createdMachine`, else `createdHuman`);
    None when it brings none that reads as a time. Validation refused those out of range."""
    try:
        machine = machine_ns(raw.get("createdMachine"))
        return machine if machine is not None else human_ns(raw.get("createdHuman"))
    except TimeRangeError:
        return None
