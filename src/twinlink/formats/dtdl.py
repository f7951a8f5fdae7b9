"""DTDL v3 (Azure Digital Twins' Digital Twins Definition Language): a twin's `interface` as a
DTDL Interface, and a DTDL v3 or v2 Interface back into an `interface` (docs/formats.md "DTDL").

The Interface's `@id` is a DTMI made from the twin's global id (`dtmi_for`), so it is stable
(the id never changes, the slug may) and the same wherever the twin is exported; a relation's
Relationship targets the DTMI of the other twin's id, known without fetching it.

What DTDL cannot say (a name outside its pattern, `min`/`max`, a unit it has no word for, a
parameter's `required`/`default`, the interface's policies) goes into the element's `comment`
as `twinlink: {json}`, a note for model authors that import reads back; so an export imports
as the interface it came from.
"""

from __future__ import annotations

import hashlib
import json
import re
from typing import Any
from urllib.parse import urlsplit

from twinlink.formats._dtdl_check import validate_dtdl
from twinlink.formats._dtdl_import import import_dtdl
from twinlink.formats._dtdl_terms import DTDL_V3_CONTEXT, INTERFACE_DTMI_MAX, NOTE_PREFIX
from twinlink.formats._dtdl_units import (
    QUANTITATIVE_CONTEXT,
    SYMBOLS,
    UNIT_SYMBOLS,
)
from twinlink.formats.context import ExportContext

__all__ = ["dtmi_for", "export_dtdl", "import_dtdl", "validate_dtdl"]

COMMENT_MAX = 512
DISPLAY_NAME_MAX = 64
DESCRIPTION_MAX = 512
# A twinlink type -> DTDL schema. `integer` is 64-bit in twinlink, DTDL's `integer` 32-bit.
SCHEMAS = {"number": "double", "integer": "long", "bool": "boolean", "string": "string"}
_NOT_NAME_CHAR = re.compile(r"[^A-Za-z0-9_]+")


def dtmi_for(global_id: str) -> str:
    """The DTMI of the twin with this global id: readable segments from the id (a URL's host
    reversed, then its path) and a last segment from the id's SHA-256, which keeps two ids
    apart that read alike (`a-b`, `a_b`). Always a valid Interface DTMI of at most 128
    characters, version 1."""
    digest = "h" + hashlib.sha256(global_id.encode()).hexdigest()[:16]
    parts = urlsplit(global_id)
    if parts.scheme and parts.netloc:
        words = list(reversed(parts.hostname.split("."))) if parts.hostname else []
        words += parts.path.split("/")
    else:
        words = re.split(r"[/:]+", global_id)
    segments = [s for s in (_segment(w) for w in words) if s]
    room = INTERFACE_DTMI_MAX - len("dtmi:") - len(digest) - len(";1")
    kept: list[str] = []
    for segment in segments:
        if sum(len(s) + 1 for s in kept) + len(segment) + 1 > room:
            break
        kept.append(segment)
    return "dtmi:" + ":".join([*kept, digest]) + ";1"


def _segment(word: str) -> str:
    """A DTMI path segment (letters, digits, `_`; a letter first; not ending in `_`)."""
    text = _NOT_NAME_CHAR.sub("_", word).strip("_")
    if text and not text[0].isalpha():
        text = "n" + text
    return text[:40].rstrip("_")


def dtdl_name(name: str) -> str:
    """`name` in DTDL's name pattern (letters, digits, `_`, a letter first, at most 512)."""
    text = _NOT_NAME_CHAR.sub("_", name).strip("_")
    if not text or not text[0].isascii() or not text[0].isalpha():
        text = "n_" + text
    return text[:512].rstrip("_")


def export_dtdl(document: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
    """The document's interface and relations as one DTDL v3 Interface."""
    global_id = str(document.get("id") or document.get("dt-id") or ctx.twin_url)
    names = _Names()
    given = document.get("interface")
    interface: dict[str, Any] = given if isinstance(given, dict) else {}
    contents: list[dict[str, Any]] = []
    for signal in interface.get("signals") or []:
        contents.append(_value_element("Telemetry", signal, names))
    for prop in interface.get("properties") or []:
        element = _value_element("Property", prop, names)
        element["writable"] = prop.get("writable") is True
        contents.append(element)
    for command in interface.get("commands") or []:
        contents.append(_command(command, names))
    for relation in document.get("relations") or []:
        contents.append(_relationship(relation, names))
    uses_units = any(isinstance(e["@type"], list) for e in _typed_elements(contents))
    out: dict[str, Any] = {
        "@context": [DTDL_V3_CONTEXT, QUANTITATIVE_CONTEXT] if uses_units else DTDL_V3_CONTEXT,
        "@id": dtmi_for(global_id),
        "@type": "Interface",
    }
    name = document.get("name")
    if isinstance(name, str) and name:
        out["displayName"] = name[:DISPLAY_NAME_MAX]
    description = document.get("description")
    if isinstance(description, str) and description:
        out["description"] = description[:DESCRIPTION_MAX]
    note: dict[str, Any] = {"id": global_id, "url": ctx.twin_url}
    if isinstance(name, str) and len(name) > DISPLAY_NAME_MAX:
        note["name"] = name  # displayName is cut; import gives the whole name back
    for policy in ("unknown_signals", "out_of_range", "default_device"):
        if policy in interface:
            note[policy] = interface[policy]
    _add_note(out, note)
    out["contents"] = contents
    return out


class _Names:
    """DTDL names are unique across an Interface's contents; twinlink's only per list."""

    def __init__(self) -> None:
        self.taken: set[str] = set()

    def claim(self, wanted: str) -> str:
        base = dtdl_name(wanted)
        name, n = base, 1
        while name in self.taken:
            n += 1
            name = f"{base[: 512 - len(str(n)) - 1]}_{n}"
        self.taken.add(name)
        return name


def _value_element(kind: str, entry: dict[str, Any], names: _Names | None) -> dict[str, Any]:
    """A Telemetry, Property, CommandRequest or Field from a signal, property or parameter."""
    original = str(entry.get("name", ""))
    name = names.claim(original) if names else dtdl_name(original)
    element: dict[str, Any] = {"@type": kind, "name": name}
    kind_type = entry.get("type", "number")
    element["schema"] = SCHEMAS.get(kind_type, "double")
    note: dict[str, Any] = {}
    if name != original:
        note["name"] = original
    unit = entry.get("unit")
    if isinstance(unit, str) and unit:
        semantic = SYMBOLS.get(unit) if kind_type in ("number", "integer") else None
        if semantic:
            element["@type"] = [kind, semantic[0]]
            element["unit"] = semantic[1]
            if UNIT_SYMBOLS[semantic[1]] != unit:
                note["unit"] = unit
        else:
            note["unit"] = unit
    for key in ("min", "max", "required", "default"):
        if entry.get(key) is not None and not (key == "required" and entry[key] is False):
            note[key] = entry[key]
    if isinstance(entry.get("description"), str):
        element["description"] = entry["description"][:DESCRIPTION_MAX]
    _add_note(element, note)
    return element


def _command(command: dict[str, Any], names: _Names) -> dict[str, Any]:
    original = str(command.get("name", ""))
    element: dict[str, Any] = {"@type": "Command", "name": names.claim(original)}
    if isinstance(command.get("description"), str):
        element["description"] = command["description"][:DESCRIPTION_MAX]
    if element["name"] != original:
        _add_note(element, {"name": original})
    parameters = [p for p in command.get("parameters") or [] if isinstance(p, dict)]
    if len(parameters) == 1:
        element["request"] = _value_element("CommandRequest", parameters[0], None)
    elif parameters:
        # DTDL gives a Command one request; several parameters are the fields of an Object.
        fields = _Names()
        element["request"] = {
            "@type": "CommandRequest",
            "name": "parameters",
            "schema": {
                "@type": "Object",
                "fields": [_value_element("Field", p, fields) for p in parameters],
            },
        }
    return element


def _relationship(relation: dict[str, Any], names: _Names) -> dict[str, Any]:
    kind = str(relation.get("relationType", "relation"))
    target = str(relation.get("id") or relation.get("dt-id") or "")
    element: dict[str, Any] = {
        "@type": "Relationship",
        "name": names.claim(kind),
        "maxMultiplicity": 1,
        "target": dtmi_for(target),
        "description": f"The {kind} twin {target}"[:DESCRIPTION_MAX],
    }
    _add_note(element, {"relationType": kind, "id": target})
    return element


def _add_note(element: dict[str, Any], note: dict[str, Any]) -> None:
    """Keep what DTDL cannot say in the element's comment, if it fits DTDL's 512 characters."""
    if not note:
        return
    text = NOTE_PREFIX + json.dumps(note, ensure_ascii=False, separators=(",", ":"))
    if len(text) <= COMMENT_MAX:
        element["comment"] = text


def _typed_elements(contents: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = list(contents)
    for element in contents:
        request = element.get("request")
        if isinstance(request, dict):
            out.append(request)
            schema = request.get("schema")
            if isinstance(schema, dict):
                out.extend(f for f in schema.get("fields", []) if isinstance(f, dict))
    return out
