"""What a deployment consists of, and a plan: what applying it creates, updates, deletes and
keeps, as `terraform plan` shows it.

Resources are compared by (type, name) and by a keyed fingerprint of their whole spec; the
spec a plan shows (and the journal stores) has its secret-looking values masked, so that a
password given as a parameter is neither answered nor stored in the clear.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import orjson

# The order things are made in: what a later kind refers to exists first (a connector speaks
# for a device; a processor's FMU ref is pinned by the processor service). Undone in reverse.
ORDER = ("twin", "device", "service", "processor", "connector")
MASK = "***"
_SECRET_KEY = re.compile(r"pass|secret|token|credential|private|api[_-]?key", re.IGNORECASE)


@dataclass(frozen=True, slots=True)
class Resource:
    type: str  # twin | device | service | processor | connector
    name: str
    spec: dict[str, Any]  # the body its service takes (the rendered document for the twin)

    @property
    def key(self) -> tuple[str, str]:
        return self.type, self.name


def shown(resource: Resource, hidden: frozenset[str] = frozenset()) -> dict[str, Any]:
    """The spec as plans show it and journals keep it: secret-looking values masked, a
    service's `auth` but its `method`, and the `hidden` texts (secret parameters' values)
    wherever they were written in."""
    masked: dict[str, Any] = _mask(_hide(resource.spec, hidden) if hidden else resource.spec)
    if resource.type == "service" and isinstance(masked.get("auth"), dict):
        masked["auth"] = {k: v if k == "method" else MASK for k, v in masked["auth"].items()}
    return masked


def _mask(value: Any) -> Any:
    if isinstance(value, dict):
        return {
            k: MASK if _SECRET_KEY.search(str(k)) and isinstance(v, str | int) else _mask(v)
            for k, v in value.items()
        }
    if isinstance(value, list):
        return [_mask(v) for v in value]
    return value


def _hide(value: Any, hidden: frozenset[str]) -> Any:
    if isinstance(value, dict):
        return {k: _hide(v, hidden) for k, v in value.items()}
    if isinstance(value, list):
        return [_hide(v, hidden) for v in value]
    if isinstance(value, str):
        for text in hidden:
            value = value.replace(text, MASK)
        return value
    if isinstance(value, int | float) and not isinstance(value, bool) and str(value) in hidden:
        return MASK
    return value


def canonical(spec: dict[str, Any]) -> bytes:
    return orjson.dumps(spec, option=orjson.OPT_SORT_KEYS)


def changes(old: Any, new: Any, path: str = "") -> list[dict[str, Any]]:
    """Where two specs differ: [{path, from, to}], leaves of mappings, lists whole."""
    if isinstance(old, dict) and isinstance(new, dict):
        out = []
        for key in [*old, *(k for k in new if k not in old)]:
            sub = f"{path}.{key}" if path else str(key)
            if key not in new:
                out.append({"path": sub, "from": old[key], "to": None})
            elif key not in old:
                out.append({"path": sub, "from": None, "to": new[key]})
            else:
                out.extend(changes(old[key], new[key], sub))
        return out
    if old != new:
        return [{"path": path or "(all)", "from": old, "to": new}]
    return []


@dataclass(slots=True)
class Plan:
    create: list[Resource] = field(default_factory=list)
    update: list[tuple[Resource, list[dict[str, Any]]]] = field(default_factory=list)
    delete: list[tuple[str, str]] = field(default_factory=list)
    keep: list[tuple[str, str]] = field(default_factory=list)
    hidden: frozenset[str] = frozenset()  # secret parameters' values, masked in `create`

    def view(self) -> dict[str, Any]:
        return {
            "create": [
                {"type": r.type, "name": r.name, "spec": shown(r, self.hidden)} for r in self.create
            ],
            "update": [{"type": r.type, "name": r.name, "changes": c} for r, c in self.update],
            "delete": [{"type": t, "name": n} for t, n in self.delete],
            "keep": [{"type": t, "name": n} for t, n in self.keep],
        }

    @property
    def empty(self) -> bool:
        return not (self.create or self.update or self.delete)


def plan_create(resources: list[Resource], hidden: frozenset[str] = frozenset()) -> Plan:
    return Plan(create=list(resources), hidden=hidden)


def plan_change(
    journal: list[dict[str, Any]],
    resources: list[Resource],
    fingerprints: dict[tuple[str, str], str],
    hidden: frozenset[str] = frozenset(),
) -> Plan:
    """From what a deployment made (its journal) to `resources`. `fingerprints` are those of
    the new resources' whole specs, as the journal keeps them. A device is compared by name
    alone: a new description is not worth a new token."""
    made = {(e["type"], e["name"]): e for e in journal}
    plan = Plan(hidden=hidden)
    for resource in resources:
        entry = made.get(resource.key)
        if entry is None:
            plan.create.append(resource)
        elif resource.type == "device" or entry.get("fingerprint") == fingerprints[resource.key]:
            plan.keep.append(resource.key)
        else:
            diff = changes(entry["spec"], shown(resource, hidden))
            # Specs equal as shown but not as given: a masked (secret) value changed.
            plan.update.append((resource, diff or [{"path": "(secret)", "from": MASK, "to": MASK}]))
    wanted = {r.key for r in resources}
    plan.delete = [
        key for key in reversed(list(made)) if key not in wanted
    ]  # made last, deleted first
    return plan
