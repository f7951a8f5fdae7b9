"""A W3C WoT Thing Description (1.0 or 1.1) read into a DT document fragment.

The reverse of wot.py's export, and general enough for TDs written elsewhere:

- a TD property that is `readOnly` and `observable` is a measured quantity: a signal; any
  other property is a property, `writable` when it is not `readOnly` and a form (or the
  default ops of a form without `op`) writes it;
- an action is a command; an object `input` gives one parameter per member (`required`
  from the schema's list), any other `input` one parameter named `value`;
- an event is a signal (its `data` schema gives the type); one whose name a signal already
  has (a TD may have a property and an event of one name) is kept under `events`.

twinlink values are numbers, booleans and text, so a TD data schema of another type (object,
array, null, or none) becomes `type: string` and keeps the TD schema under `schema`, where a
person (or a later export) can read it. Keys of an affordance that have no twinlink meaning
(`title`, `@type`, `enum`, `output`, ...) are kept on the entry as they are: interface entries
may carry other keys.
"""

from __future__ import annotations

import math
from typing import Any

_TYPES = {"number": "number", "integer": "integer", "boolean": "bool", "string": "string"}
# TD keys that the mapping below turns into twinlink keys (or drops: forms are this Thing's
# endpoints elsewhere, meaningless once the twin lives here).
_SCHEMA_KEYS = {"type", "minimum", "maximum", "unit", "description", "default"}
_AFFORDANCE_KEYS = _SCHEMA_KEYS | {
    "forms",
    "readOnly",
    "writeOnly",
    "observable",
    "uriVariables",
    "input",
    "data",
    "safe",
    "idempotent",
}
# twinlink's own keys of an entry: a TD key of the same name is not copied over them.
_OURS = {"name", "type", "min", "max", "unit", "description", "writable", "required", "default"}
_OURS |= {"parameters", "schema", "title"}
# Terms of an affordance that are not its data schema (the description is the entry's).
_NOT_SCHEMA = {"forms", "uriVariables", "readOnly", "writeOnly", "observable", "description"}
POLICY_TERM = "twinlink:interface"
_POLICIES = ("default_device", "unknown_signals", "out_of_range")


def import_wot(data: dict[str, Any]) -> dict[str, Any]:
    """The DT document fragment of a TD: name, description, id and `interface`."""
    if not isinstance(data, dict):
        raise TypeError("a Thing Description is a JSON object")
    fragment: dict[str, Any] = {}
    if isinstance(data.get("id"), str) and data["id"]:
        fragment["id"] = data["id"]
    title = data.get("title", data.get("name"))  # `name` in TD drafts before 1.0
    if isinstance(title, str) and title:
        fragment["name"] = title
    if isinstance(data.get("description"), str) and data["description"]:
        fragment["description"] = data["description"]
    signals: list[dict[str, Any]] = []
    properties: list[dict[str, Any]] = []
    for name, affordance in _affordances(data, "properties"):
        if affordance.get("readOnly") is True and affordance.get("observable") is True:
            signals.append(_entry(name, affordance))
        else:
            properties.append({**_entry(name, affordance), "writable": _writable(affordance)})
    taken = {s["name"] for s in signals}
    events: list[dict[str, Any]] = []  # those whose name an observable property has
    for name, affordance in _affordances(data, "events"):
        entry = _entry(name, _event_schema(affordance))
        (events if name in taken else signals).append(entry)
    commands = [_command(name, a) for name, a in _affordances(data, "actions")]
    interface: dict[str, Any] = {"signals": signals, "properties": properties, "commands": commands}
    if events:  # signal names are unique: kept beside them, as an interface's other keys are
        interface["events"] = events
    policies = data.get(POLICY_TERM)
    if isinstance(policies, dict):
        interface.update({k: policies[k] for k in _POLICIES if k in policies})
    fragment["interface"] = interface
    return fragment


def _affordances(data: dict[str, Any], kind: str) -> list[tuple[str, dict[str, Any]]]:
    found = data.get(kind)
    if not isinstance(found, dict):
        return []
    return [(str(k), v) for k, v in found.items() if isinstance(v, dict)]


def _entry(name: str, schema: dict[str, Any]) -> dict[str, Any]:
    """A signal, property or parameter from a TD data schema."""
    entry: dict[str, Any] = {"name": name}
    td_type = schema.get("type")
    entry["type"] = _TYPES.get(td_type, "string") if isinstance(td_type, str) else "string"
    scalar = td_type in _TYPES
    if not scalar:
        kept = {k: v for k, v in schema.items() if k not in _NOT_SCHEMA}
        entry["schema"] = kept  # twinlink carries it as text; what it holds stays readable
    numeric = entry["type"] in ("number", "integer")
    low, high = _number(schema.get("minimum")), _number(schema.get("maximum"))
    if numeric and low is not None and (high is None or low <= high):
        entry["min"] = low
    if numeric and high is not None and (low is None or low <= high):
        entry["max"] = high
    if isinstance(schema.get("unit"), str) and schema["unit"]:
        entry["unit"] = schema["unit"]
    description = schema.get("description", schema.get("title"))
    if isinstance(description, str) and description:
        entry["description"] = description
    if scalar:
        entry.update({k: v for k, v in schema.items() if k not in _AFFORDANCE_KEYS | _OURS})
    return entry


def _number(value: Any) -> int | float | None:
    """A bound twinlink accepts: finite, and an integer within 64 bits."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, int) and not -(2**63) <= value < 2**63:
        return None
    return value


def _writable(affordance: dict[str, Any]) -> bool:
    if affordance.get("readOnly") is True:
        return False
    forms = affordance.get("forms")
    for form in forms if isinstance(forms, list) else []:
        if not isinstance(form, dict):
            continue
        op = form.get("op")
        if op is None:  # a property form without op reads and writes (TD 1.1, 5.4.1)
            return True
        if op == "writeproperty" or (isinstance(op, list) and "writeproperty" in op):
            return True
    return False


def _event_schema(affordance: dict[str, Any]) -> dict[str, Any]:
    """An event's `data` schema, described as the event is."""
    data = affordance.get("data")
    schema: dict[str, Any] = dict(data) if isinstance(data, dict) else {}
    for key in ("description", "title"):
        if key in affordance and key not in schema:
            schema[key] = affordance[key]
    return schema


def _command(name: str, action: dict[str, Any]) -> dict[str, Any]:
    command: dict[str, Any] = {"name": name}
    description = action.get("description", action.get("title"))
    if isinstance(description, str) and description:
        command["description"] = description
    command["parameters"] = _parameters(action.get("input"))
    command.update({k: v for k, v in action.items() if k not in _AFFORDANCE_KEYS | _OURS})
    return command


def _parameters(schema: Any) -> list[dict[str, Any]]:
    if not isinstance(schema, dict):
        return []
    members = schema.get("properties")
    if schema.get("type") == "object" and isinstance(members, dict):
        required = schema.get("required")
        needed = set(required) if isinstance(required, list) else set()
        out = []
        for name, member in members.items():
            entry = _entry(str(name), member if isinstance(member, dict) else {})
            _default(entry, member)
            entry["required"] = name in needed
            out.append(entry)
        return out
    # A scalar (or other) input: the command's one argument.
    entry = _entry("value", schema)
    _default(entry, schema)
    entry["required"] = True
    return [entry]


def _default(entry: dict[str, Any], schema: Any) -> None:
    if isinstance(schema, dict) and schema.get("default") is not None:
        entry["default"] = schema["default"]
