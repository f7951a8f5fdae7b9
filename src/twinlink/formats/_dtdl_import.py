"""DTDL v3 or v2 Interface -> a DT document fragment (docs/formats.md "DTDL").

Telemetry and Properties become signals and properties, Commands commands (an Object request's
fields are the parameters); the note an export of twinlink left in `comment` gives back what
DTDL could not say. What twinlink cannot type (Components, Objects, Maps, Arrays, geospatial
schemas, the Relationships of other models) is kept as written in `interface.dtdlOther`.
"""

from __future__ import annotations

import json
from typing import Any

from twinlink.domain.errors import InvalidInputError
from twinlink.formats._dtdl_terms import NOTE_PREFIX
from twinlink.formats._dtdl_units import UNIT_SYMBOLS

# DTDL schema -> twinlink type; date and time values travel as ISO 8601 text.
TYPES = {
    "double": "number",
    "float": "number",
    "integer": "integer",
    "long": "integer",
    "boolean": "bool",
    "string": "string",
    "date": "string",
    "dateTime": "string",
    "duration": "string",
    "time": "string",
}
RELATION_TYPES = ("parent", "child", "sibling")


def import_dtdl(data: dict[str, Any] | list[Any]) -> dict[str, Any]:
    """A DT document fragment (`name`, `description`, `id` when the Interface came from
    twinlink, `interface`, `relations` from twinlink's own Relationships) from a DTDL v3 or
    v2 Interface. Contents twinlink cannot type are kept in `interface.dtdlOther`."""
    if isinstance(data, list):
        interfaces = [d for d in data if isinstance(d, dict) and _types(d) == {"Interface"}]
        if len(interfaces) != 1:
            raise InvalidInputError(
                f"the DTDL model holds {len(interfaces)} Interfaces; import reads one: "
                "give the Interface of the twin alone"
            )
        data = interfaces[0]
    if not isinstance(data, dict) or "Interface" not in _types(data):
        raise InvalidInputError(
            'a DTDL import needs an Interface: a JSON object with "@type": "Interface"'
        )
    note = _note(data)
    fragment: dict[str, Any] = {}
    if isinstance(note.get("id"), str):
        fragment["id"] = note["id"]
    name = note.get("name") or _text(data.get("displayName")) or _last_segment(data.get("@id"))
    if name:
        fragment["name"] = name
    description = _text(data.get("description"))
    if description:
        fragment["description"] = description
    interface: dict[str, Any] = {"signals": [], "properties": [], "commands": []}
    relations: list[dict[str, Any]] = []
    other: list[Any] = []
    contents = data.get("contents") or []
    for element in contents if isinstance(contents, list) else [contents]:
        _import_element(element, interface, relations, other)
    for policy in ("unknown_signals", "out_of_range", "default_device"):
        if policy in note:
            interface[policy] = note[policy]
    if other:
        interface["dtdlOther"] = other
    fragment["interface"] = interface
    if relations:
        fragment["relations"] = relations
    return fragment


def _import_element(
    element: Any, interface: dict[str, Any], relations: list[dict[str, Any]], other: list[Any]
) -> None:
    types = _types(element) if isinstance(element, dict) else set()
    if "Telemetry" in types or "Property" in types:
        entry = _value_entry(element)
        if entry is None:
            other.append(element)
        elif "Property" in types:
            entry["writable"] = element.get("writable") is True
            interface["properties"].append(entry)
        else:
            interface["signals"].append(entry)
    elif "Command" in types:
        command = _command_entry(element)
        (interface["commands"] if command else other).append(command or element)
    elif "Relationship" in types and _note(element).get("relationType") in RELATION_TYPES:
        note = _note(element)
        relations.append({"relationType": note["relationType"], "id": note.get("id")})
    else:
        other.append(element)  # a Component, a Relationship of another model


def _value_entry(element: dict[str, Any]) -> dict[str, Any] | None:
    """A signal, property or parameter; None when its schema has no twinlink type."""
    note = _note(element)
    schema = element.get("schema")
    schema = schema[0] if isinstance(schema, list) and len(schema) == 1 else schema
    kind = _schema_type(schema)
    if kind is None:
        return None
    entry: dict[str, Any] = {"name": note.get("name") or _text(element.get("name"))}
    unit = note.get("unit") or UNIT_SYMBOLS.get(str(element.get("unit")))
    if unit is None and isinstance(element.get("unit"), str):
        unit = element["unit"]  # a DTDL unit twinlink has no symbol for: kept as DTDL says it
    if unit:
        entry["unit"] = unit
    entry["type"] = kind
    for key in ("min", "max"):
        if key in note:
            entry[key] = note[key]
    description = _text(element.get("description"))
    if description:
        entry["description"] = description
    if isinstance(schema, dict) and "Enum" in _types(schema):
        entry["enum"] = [v.get("enumValue") for v in schema.get("enumValues", [])]
    elif isinstance(schema, str) and kind == "string" and schema != "string":
        entry["dtdlSchema"] = schema  # date, dateTime, duration, time: what the text holds
    for key in ("required", "default"):
        if key in note:
            entry[key] = note[key]
    return entry


def _schema_type(schema: Any) -> str | None:
    if isinstance(schema, str):
        return TYPES.get(schema.removeprefix("dtmi:dtdl:instance:Schema:").split(";")[0])
    if isinstance(schema, dict) and "Enum" in _types(schema):
        return TYPES.get(str(schema.get("valueSchema")))
    return None


def _command_entry(element: dict[str, Any]) -> dict[str, Any] | None:
    note = _note(element)
    command: dict[str, Any] = {"name": note.get("name") or _text(element.get("name"))}
    description = _text(element.get("description"))
    if description:
        command["description"] = description
    request = element.get("request") or element.get("commandRequest")
    request = request[0] if isinstance(request, list) and len(request) == 1 else request
    parameters: list[dict[str, Any]] = []
    if isinstance(request, dict):
        schema = request.get("schema")
        if isinstance(schema, dict) and "Object" in _types(schema):
            for field in schema.get("fields") or []:
                entry = _value_entry(field) if isinstance(field, dict) else None
                if entry is None:
                    return None
                parameters.append(entry)
        else:
            entry = _value_entry(request)
            if entry is None:
                return None
            parameters.append(entry)
    command["parameters"] = parameters
    if "response" in element:
        command["dtdlResponse"] = element["response"]  # twinlink's commands answer no value
    return command


def _types(element: dict[str, Any]) -> set[str]:
    kinds = element.get("@type")
    values = kinds if isinstance(kinds, list) else [kinds]
    return {str(v).removeprefix("dtmi:dtdl:class:").split(";")[0] for v in values}


def _note(element: Any) -> dict[str, Any]:
    comment = element.get("comment") if isinstance(element, dict) else None
    if not isinstance(comment, str) or not comment.startswith(NOTE_PREFIX):
        return {}
    try:
        note = json.loads(comment[len(NOTE_PREFIX) :])
    except ValueError:
        return {}
    return note if isinstance(note, dict) else {}


def _text(value: Any) -> str | None:
    """A localizable string's English (or first) text."""
    if isinstance(value, dict) and "@value" in value:
        value = value["@value"]
    if isinstance(value, str):
        return value
    if isinstance(value, dict) and value:
        for lang in ("en", "en-US", "en-GB"):
            if isinstance(value.get(lang), str):
                return str(value[lang])
        first = next(iter(value.values()))
        return first if isinstance(first, str) else None
    if isinstance(value, list) and value:
        return _text(value[0])
    return None


def _last_segment(dtmi: Any) -> str | None:
    if not isinstance(dtmi, str) or not dtmi.startswith("dtmi:"):
        return None
    return dtmi.split(";")[0].rsplit(":", 1)[-1]
