"""The terms and limits of DTDL v3 (DTDL/v3/DTDL.Specification.v3.md and the limits tables
of DTDL.v3.md in Azure/opendigitaltwins-dtdl), shared by the checker, the export and the import.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

from twinlink.formats._dtdl_units import QUANTITATIVE_CONTEXT

# An export's note for what DTDL cannot say, in an element's `comment` (docs/formats.md "DTDL").
NOTE_PREFIX = "twinlink: "
DTDL_V3_CONTEXT = "dtmi:dtdl:context;3"
DTDL_V2_CONTEXT = "dtmi:dtdl:context;2"
DTMI = re.compile(
    r"^dtmi:[A-Za-z](?:[A-Za-z0-9_]*[A-Za-z0-9])?(?::[A-Za-z](?:[A-Za-z0-9_]*[A-Za-z0-9])?)*"
    r"(?:;[1-9][0-9]{0,8}(?:\.[1-9][0-9]{0,5})?)?$"
)
NAME_PATTERN = re.compile(r"^[A-Za-z](?:[A-Za-z0-9_]*[A-Za-z0-9])?$")
LANGUAGE = re.compile(r"^[a-z]{2,4}(-[A-Z][a-z]{3})?(-([A-Z]{2}|[0-9]{3}))?$")
INTERFACE_DTMI_MAX = 128
DTMI_MAX = 2048
NAME_MAX = 512
# The specification's limits; DTDL.v3.md's tables say 64 for displayName, but the normative
# text and Microsoft's DTDLParser allow 512 (the export keeps to 64 all the same).
TEXT_MAX = {"comment": 512, "description": 512, "displayName": 512}
MAX_ELEMENTS = 100_000
MAX_SCHEMA_DEPTH = 5
MAX_EXTENDS = 1024
MAX_BYTES = 1024 * 1024
RESERVED_PREFIXES = ("dtmi:dtdl:", "dtmi:standard:")
PRIMITIVE = {"boolean", "date", "dateTime", "double", "duration", "float", "integer"}
PRIMITIVE |= {"long", "string", "time"}
GEOSPATIAL = {"lineString", "multiLineString", "multiPoint", "multiPolygon", "point", "polygon"}
NUMERIC = {"double", "float", "integer", "long"}
CONTENT_TYPES = ("Command", "Component", "Property", "Relationship", "Telemetry")
COMPLEX_TYPES = ("Array", "Enum", "Map", "Object")
COMMON = {"@context", "@id", "@type", "comment", "description", "displayName"}
MEMBERS: dict[str, set[str]] = {
    "Interface": {"contents", "extends", "schemas"},
    "Telemetry": {"name", "schema"},
    "Property": {"name", "schema", "writable"},
    "Command": {"name", "request", "response"},
    "CommandRequest": {"name", "schema"},
    "CommandResponse": {"name", "schema"},
    "Relationship": {"maxMultiplicity", "minMultiplicity", "name", "properties", "target"},
    "Component": {"name", "schema"},
    "Array": {"elementSchema"},
    "Enum": {"enumValues", "valueSchema"},
    "EnumValue": {"enumValue", "name"},
    "Map": {"mapKey", "mapValue"},
    "MapKey": {"name", "schema"},
    "MapValue": {"name", "schema"},
    "Object": {"fields"},
    "Field": {"name", "schema"},
}
MEMBERS["Relationship"].add("writable")
REQUIRED: dict[str, tuple[str, ...]] = {
    "Interface": ("@id", "@type"),
    "Telemetry": ("@type", "name", "schema"),
    "Property": ("@type", "name", "schema"),
    "Command": ("@type", "name"),
    "CommandRequest": ("name", "schema"),
    "CommandResponse": ("name", "schema"),
    "Relationship": ("@type", "name"),
    "Component": ("@type", "name", "schema"),
    "Array": ("@type", "elementSchema"),
    "Enum": ("@type", "enumValues", "valueSchema"),
    "EnumValue": ("enumValue", "name"),
    "Map": ("@type", "mapKey", "mapValue"),
    "MapKey": ("name", "schema"),
    "MapValue": ("name", "schema"),
    "Object": ("@type", "fields"),
    "Field": ("name", "schema"),
}
# Element types a QuantitativeTypes semantic type may co-type (and then give a `unit`).
SEMANTIC_HOSTS = {"CommandRequest", "CommandResponse", "Field", "MapValue", "Property"}
SEMANTIC_HOSTS.add("Telemetry")
KNOWN_CONTEXTS = {DTDL_V3_CONTEXT, DTDL_V2_CONTEXT, QUANTITATIVE_CONTEXT}
# DTDL v2 differs in a few rules this checker applies: names of at most 64 characters, at
# most 300 contents, semantic types built in, CommandPayload for requests and responses.
V2_NAME_MAX = 64
V2_MAX_CONTENTS = 300


def element_texts(value: Any, plain: bool) -> Iterator[str | None]:
    """The strings of a (localizable) string; None for a value of the wrong form."""
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict) and "@value" in value:
        yield value["@value"] if isinstance(value["@value"], str) else None
    elif isinstance(value, dict) and not plain:
        for lang, text in value.items():
            yield text if LANGUAGE.match(lang) and isinstance(text, str) else None
    elif isinstance(value, list) and not plain:
        for item in value:
            yield from element_texts(item, plain=True)
    else:
        yield None


def member_term(member: str) -> str:
    if member.startswith("dtmi:dtdl:property:") and member.endswith(";3"):
        return member[len("dtmi:dtdl:property:") : -2]
    return member


def as_list(value: Any) -> list[Any]:
    if value is None:
        return []
    return value if isinstance(value, list) else [value]


def is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def at(path: str, member: str) -> str:
    return f"{path}.{member}" if path and not member.startswith("[") else path + member
