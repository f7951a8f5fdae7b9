"""Merging a twin's privacy parts into the one document a reader sees.

The published spec splits a twin into documents by privacy (public, group-1, private, ...),
all with the same id. The reader's view merges the parts they may see, from the most public
to the most private: mappings merge key by key, features and interface entries merge by name,
and a later (more private) value wins.
"""

from __future__ import annotations

from typing import Any

from twinlink.domain.document import PLATFORM_KEYS

_BY_NAME = ("features",)
_INTERFACE_LISTS = ("signals", "properties", "commands")


def level_order(level: str) -> tuple[int, str]:
    """Sort key: public first, group levels by name, private last."""
    if level == "public":
        return (0, "")
    if level == "private":
        return (2, "")
    return (1, level)


def most_private(levels: list[str]) -> str:
    return max(levels, key=level_order) if levels else "public"


def merge_parts(parts: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Merge parts (privacy level -> document) into one document, most public first."""
    merged: dict[str, Any] = {}
    for level in sorted(parts, key=level_order):
        _merge_into(merged, parts[level], top=True)
    if parts:
        merged["privacy"] = most_private(list(parts))
    return merged


def _merge_into(target: dict[str, Any], source: dict[str, Any], top: bool = False) -> None:
    for key, value in source.items():
        if top and key in ("relations", *PLATFORM_KEYS):
            continue  # relations come from the relation graph; timestamps from the platform
        old = target.get(key)
        if top and key in _BY_NAME and isinstance(old, list) and isinstance(value, list):
            target[key] = _merge_named(old, value)
        elif top and key == "interface" and isinstance(old, dict) and isinstance(value, dict):
            merged = dict(old)
            for section, items in value.items():
                prior = merged.get(section)
                if (
                    section in _INTERFACE_LISTS
                    and isinstance(prior, list)
                    and isinstance(items, list)
                ):
                    merged[section] = _merge_named(prior, items)
                else:
                    merged[section] = items
            target[key] = merged
        elif isinstance(old, dict) and isinstance(value, dict):
            copy = dict(old)
            _merge_into(copy, value)
            target[key] = copy
        else:
            target[key] = value


def _merge_named(old: list[Any], new: list[Any]) -> list[Any]:
    out = [dict(x) if isinstance(x, dict) else x for x in old]
    index = {x.get("name"): i for i, x in enumerate(out) if isinstance(x, dict)}
    for item in new:
        name = item.get("name") if isinstance(item, dict) else None
        if name is not None and name in index:
            _merge_into(out[index[name]], item)
        else:
            out.append(item)
    return out
