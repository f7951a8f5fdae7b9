"""The rules of the DTDL v3 specification, checked on a model as JSON (docs/formats.md "DTDL").

From DTDL/v3/DTDL.Specification.v3.md (the normative text) and DTDL.v3.md (its limits
tables) in Azure/opendigitaltwins-dtdl: DTMI syntax and lengths, the members each element
type must and may have, names, localizable strings, schemas, Command requests and responses,
Relationships, the QuantitativeTypes extension's semantic types and units, and the limits on
nesting, element counts and size. Each problem names the path of the value at fault.
"""

from __future__ import annotations

import json
from typing import Any

from twinlink.formats._dtdl_terms import (
    COMMON,
    COMPLEX_TYPES,
    CONTENT_TYPES,
    DTDL_V2_CONTEXT,
    DTDL_V3_CONTEXT,
    DTMI,
    DTMI_MAX,
    GEOSPATIAL,
    INTERFACE_DTMI_MAX,
    KNOWN_CONTEXTS,
    MAX_BYTES,
    MAX_ELEMENTS,
    MAX_EXTENDS,
    MAX_SCHEMA_DEPTH,
    MEMBERS,
    NAME_MAX,
    NAME_PATTERN,
    NUMERIC,
    PRIMITIVE,
    REQUIRED,
    RESERVED_PREFIXES,
    SEMANTIC_HOSTS,
    TEXT_MAX,
    V2_MAX_CONTENTS,
    V2_NAME_MAX,
    as_list,
    at,
    element_texts,
    is_int,
    member_term,
)
from twinlink.formats._dtdl_units import QUANTITATIVE_CONTEXT, SEMANTIC_TYPES, UNIT_TYPES


def validate_dtdl(data: dict[str, Any] | list[Any]) -> list[str]:
    """The problems of a DTDL v3 model (one Interface, or a list of them); empty when valid."""
    return _Checker(data).run()


PAYLOADS = ("CommandRequest", "CommandResponse")


class _Checker:
    def __init__(self, data: Any) -> None:
        self.data = data
        self.problems: list[str] = []
        self.ids: dict[str, str] = {}  # @id -> the path that declared it first
        self.references: list[tuple[str, str]] = []  # (DTMI, path) of schema references
        self.elements = 0
        self.language = DTDL_V3_CONTEXT  # the DTDL context of the Interface being checked

    @property
    def v2(self) -> bool:
        return self.language == DTDL_V2_CONTEXT

    def run(self) -> list[str]:
        roots = self.data if isinstance(self.data, list) else [self.data]
        if not roots or not all(isinstance(r, dict) for r in roots):
            return ["a DTDL model is a JSON object (an Interface) or an array of them"]
        for index, root in enumerate(roots):
            path = f"[{index}]" if isinstance(self.data, list) else ""
            self.elements = 0
            contexts = as_list(root.get("@context"))
            self.language = DTDL_V2_CONTEXT if DTDL_V2_CONTEXT in contexts else DTDL_V3_CONTEXT
            if self._kind_of(root, path, ("Interface",)):
                self._interface(root, path, [], top=True)
            size = len(json.dumps(root, ensure_ascii=False).encode())
            if size > MAX_BYTES:
                self.problem(path, f"the Interface is {size} bytes of JSON; DTDL allows 1 MiB")
        for dtmi, path in self.references:
            if dtmi not in self.ids and not dtmi.startswith(RESERVED_PREFIXES):
                self.problem(
                    path,
                    f"{dtmi} is not defined in this model (the model is incomplete): "
                    "define it in the model (a schema in the Interface's `schemas`), or inline",
                )
        return self.problems

    def problem(self, path: str, message: str) -> None:
        self.problems.append(f"{path or '(Interface)'}: {message}")

    # -- elements ------------------------------------------------------------------------

    def _interface(self, node: dict[str, Any], path: str, context: list[str], top: bool) -> None:
        if top and "@context" not in node:
            self.problem(path, f'an Interface at the top needs "@context": "{DTDL_V3_CONTEXT}"')
        context = self._context(node, path, context, top)
        if not self._element(node, path, "Interface", context):
            return
        contents = as_list(node.get("contents"))
        if self.v2 and len(contents) > V2_MAX_CONTENTS:
            self.problem(at(path, "contents"), f"DTDL v2 allows {V2_MAX_CONTENTS} contents")
        names: dict[str, str] = {}
        for i, child in enumerate(contents):
            child_path = at(path, f"contents[{i}]")
            kind = self._kind_of(child, child_path, CONTENT_TYPES)
            if kind:
                self._content(child, child_path, kind, context)
                self._unique_name(child, child_path, names, "contents of the Interface")
        for i, schema in enumerate(as_list(node.get("schemas"))):
            schema_path = at(path, f"schemas[{i}]")
            if isinstance(schema, dict) and "@id" not in schema:
                self.problem(schema_path, "a schema in `schemas` needs an @id")
            self._schema(schema, schema_path, context, 0)
        extends = as_list(node.get("extends"))
        if len(extends) > MAX_EXTENDS:
            self.problem(at(path, "extends"), f"more than {MAX_EXTENDS} Interfaces")
        for i, parent in enumerate(extends):
            parent_path = at(path, f"extends[{i}]")
            if isinstance(parent, dict):
                self._interface(parent, parent_path, context, top=False)
            elif isinstance(parent, str) and DTMI.match(parent):
                self.references.append((parent, parent_path))
            else:
                self.problem(parent_path, "`extends` takes DTMIs or Interfaces")
        if top and self.elements > MAX_ELEMENTS:
            self.problem(path, f"{self.elements} elements under contents; DTDL allows 100000")

    def _content(self, node: dict[str, Any], path: str, kind: str, context: list[str]) -> None:
        context = self._context(node, path, context, False)
        if not self._element(node, path, kind, context):
            return
        if kind in ("Telemetry", "Property"):
            self._schema(node.get("schema"), at(path, "schema"), context, 0)
        if kind == "Property" and "writable" in node and not isinstance(node["writable"], bool):
            self.problem(at(path, "writable"), "must be true or false")
        if kind == "Command":
            for member in ("request", "response"):
                if member in node:
                    self._payload(node[member], at(path, member), member, context)
        if kind == "Relationship":
            self._relationship(node, path, context)
        if kind == "Component":
            schema = node.get("schema")
            if isinstance(schema, dict):
                self._interface(schema, at(path, "schema"), context, top=False)
            elif isinstance(schema, str) and DTMI.match(schema):
                self.references.append((schema, at(path, "schema")))
            else:
                self.problem(at(path, "schema"), "a Component's schema is an Interface")

    def _payload(self, value: Any, path: str, member: str, context: list[str]) -> None:
        if isinstance(value, list):
            if len(value) != 1:
                self.problem(path, f"a Command has one {member} (an Object for several values)")
                return
            value = value[0]
        kind = "CommandRequest" if member == "request" else "CommandResponse"
        if not isinstance(value, dict):
            self.problem(path, f"must be a {kind}: an object with name and schema")
            return
        kinds = (kind, "CommandPayload") if self.v2 else (kind,)
        if "@type" in value and not self._kind_of(value, path, kinds):
            return
        if self._element(value, path, kind, context):
            self._schema(value.get("schema"), at(path, "schema"), context, 0)

    def _relationship(self, node: dict[str, Any], path: str, context: list[str]) -> None:
        if "target" in node and not (
            isinstance(node["target"], str) and DTMI.match(node["target"])
        ):
            self.problem(at(path, "target"), "must be a DTMI (the target Interface)")
        low, high = node.get("minMultiplicity"), node.get("maxMultiplicity")
        if low is not None and low != 0:
            self.problem(at(path, "minMultiplicity"), "must be 0 in DTDL v3")
        if high is not None and not (is_int(high) and high >= 1):
            self.problem(at(path, "maxMultiplicity"), "must be an integer of at least 1")
        names: dict[str, str] = {}
        for i, prop in enumerate(as_list(node.get("properties"))):
            prop_path = at(path, f"properties[{i}]")
            if self._kind_of(prop, prop_path, ("Property",)):
                self._content(prop, prop_path, "Property", context)
                self._unique_name(prop, prop_path, names, "properties of the Relationship")

    def _schema(self, value: Any, path: str, context: list[str], depth: int) -> None:
        value = value[0] if isinstance(value, list) and len(value) == 1 else value
        if isinstance(value, str):
            term = value.removeprefix("dtmi:dtdl:instance:Schema:").removeprefix(
                "dtmi:standard:schema:geospatial:"
            )
            if term.split(";")[0] in PRIMITIVE | GEOSPATIAL:
                return
            if DTMI.match(value):
                self.references.append((value, path))
                return
            self.problem(path, f"{value!r} is not a DTDL schema (double, string, ...) or a DTMI")
            return
        if not isinstance(value, dict):
            self.problem(path, "a schema is a standard schema's name, a DTMI or an element")
            return
        if depth >= MAX_SCHEMA_DEPTH:
            self.problem(path, f"schemas nest more than {MAX_SCHEMA_DEPTH} levels deep")
            return
        kind = self._kind_of(value, path, COMPLEX_TYPES)
        context = self._context(value, path, context, False)
        if not kind or not self._element(value, path, kind, context):
            return
        if kind == "Array":
            self._schema(value.get("elementSchema"), at(path, "elementSchema"), context, depth + 1)
        elif kind == "Map":
            self._map(value, path, context, depth)
        elif kind == "Object":
            names: dict[str, str] = {}
            for i, field in enumerate(as_list(value.get("fields"))):
                self._field(field, at(path, f"fields[{i}]"), "Field", context, depth, names)
        elif kind == "Enum":
            self._enum(value, path, context)

    def _field(
        self, node: Any, path: str, kind: str, ctx: list[str], depth: int, names: dict[str, str]
    ) -> None:
        if not isinstance(node, dict):
            self.problem(path, f"must be a {kind}: an object with name and schema")
            return
        if "@type" in node and not self._kind_of(node, path, (kind,)):
            return
        if self._element(node, path, kind, ctx):
            self._schema(node.get("schema"), at(path, "schema"), ctx, depth + 1)
            self._unique_name(node, path, names, "fields of the Object")

    def _map(self, node: dict[str, Any], path: str, context: list[str], depth: int) -> None:
        key = node.get("mapKey")
        if isinstance(key, dict) and "@type" not in key:
            self._element(key, at(path, "mapKey"), "MapKey", context)
            if key.get("schema") != "string":
                self.problem(at(path, "mapKey.schema"), 'a map key\'s schema must be "string"')
        self._field(node.get("mapValue"), at(path, "mapValue"), "MapValue", context, depth, {})

    def _enum(self, node: dict[str, Any], path: str, context: list[str]) -> None:
        value_schema = node.get("valueSchema")
        if value_schema not in ("integer", "string"):
            self.problem(at(path, "valueSchema"), 'must be "integer" or "string"')
        names: dict[str, str] = {}
        values: set[Any] = set()
        for i, item in enumerate(as_list(node.get("enumValues"))):
            item_path = at(path, f"enumValues[{i}]")
            if not isinstance(item, dict) or not self._element(
                item, item_path, "EnumValue", context
            ):
                continue
            self._unique_name(item, item_path, names, "values of the Enum")
            value = item.get("enumValue")
            wanted = int if value_schema == "integer" else str
            if not isinstance(value, wanted) or isinstance(value, bool):
                self.problem(
                    at(item_path, "enumValue"), f"must be {value_schema} as valueSchema says"
                )
            elif value in values:
                self.problem(at(item_path, "enumValue"), f"{value!r} is given twice")
            values.add(value)

    # -- members common to every element -------------------------------------------------

    def _element(self, node: dict[str, Any], path: str, kind: str, context: list[str]) -> bool:
        """Type, id, members, names and texts of one element; False when it is unusable."""
        self.elements += 1
        co_types = self._co_types(node, path, kind, context)
        informal = co_types is None
        allowed = COMMON | MEMBERS[kind]
        if co_types and kind in SEMANTIC_HOSTS:
            allowed = allowed | {"unit"}
            self._unit(node, path, co_types)
        for member in REQUIRED[kind]:
            if member not in node:
                self.problem(path, f"a {kind} needs `{member}`")
        for member in node:
            term = member_term(member)
            if term != member and term in node:
                self.problem(at(path, member), f"`{term}` is given twice (also as a DTMI)")
            if member.startswith("@") and member not in ("@context", "@id", "@type"):
                self.problem(at(path, member), f"{member} is not allowed in a DTDL element")
            elif ":" in member and not member.startswith("dtmi:") and not member.startswith("@"):
                self.problem(at(path, member), "a member name with ':' must be a DTMI")
            elif not informal and not member.startswith("@") and term not in allowed:
                self.problem(at(path, member), f"a {kind} has no member `{member}`")
        if "@id" in node:
            self._id(node["@id"], at(path, "@id"), kind)
        if "name" in node:
            self._name(node["name"], at(path, "name"))
        for member, limit in TEXT_MAX.items():
            if member in node:
                self._text(node[member], at(path, member), limit, member == "comment")
        return True

    def _co_types(
        self, node: dict[str, Any], path: str, kind: str, context: list[str]
    ) -> list[str] | None:
        """The semantic types co-typing the element; None when it is informally co-typed
        (a co-type of an extension this checker does not know)."""
        types = node.get("@type", [kind])
        types = types if isinstance(types, list) else [types]
        co_types: list[str] = []
        informal = False
        for value in types:
            if not isinstance(value, str):
                self.problem(at(path, "@type"), "must be a string or an array of strings")
                continue
            term = value.removeprefix("dtmi:dtdl:class:").split(";")[0]
            if term == kind or (self.v2 and term == "CommandPayload" and kind in PAYLOADS):
                continue
            if ":" in value and not DTMI.match(value):
                self.problem(at(path, "@type"), f"{value!r} is neither a DTDL term nor a DTMI")
            elif term in SEMANTIC_TYPES and (self.v2 or QUANTITATIVE_CONTEXT in context):
                if kind not in SEMANTIC_HOSTS:
                    self.problem(at(path, "@type"), f"a {kind} cannot be a {term}")
                co_types.append(term)
            elif any(c not in KNOWN_CONTEXTS for c in context):
                informal = True  # defined, perhaps, by an extension we do not know
            else:
                hint = (
                    f" (a semantic type: add {QUANTITATIVE_CONTEXT} to @context)"
                    if term in SEMANTIC_TYPES
                    else ""
                )
                self.problem(at(path, "@type"), f"{value!r} is not defined{hint}")
        return None if informal else co_types

    def _unit(self, node: dict[str, Any], path: str, co_types: list[str]) -> None:
        for semantic in co_types:
            unit_type = SEMANTIC_TYPES[semantic]
            if node.get("unit") not in UNIT_TYPES[unit_type]:
                self.problem(
                    at(path, "unit"),
                    f"a {semantic} needs a unit of {unit_type} "
                    f"({', '.join(sorted(UNIT_TYPES[unit_type])[:4])}, ...)",
                )
        schema = node.get("schema")
        if "schema" in node and schema not in NUMERIC:
            self.problem(at(path, "schema"), "a semantic type needs a numeric schema")

    def _kind_of(self, node: Any, path: str, kinds: tuple[str, ...]) -> str | None:
        if not isinstance(node, dict):
            self.problem(path, f"must be an element ({', '.join(kinds)})")
            return None
        types = node.get("@type")
        values = types if isinstance(types, list) else [types]
        terms = {str(v).removeprefix("dtmi:dtdl:class:").split(";")[0] for v in values}
        for kind in kinds:
            if kind in terms:
                return kind
        self.problem(at(path, "@type"), f"must include one of {', '.join(kinds)}")
        return None

    def _context(self, node: dict[str, Any], path: str, outer: list[str], top: bool) -> list[str]:
        if "@context" not in node:
            return outer
        value = node["@context"]
        values = value if isinstance(value, list) else [value]
        cpath = at(path, "@context")
        if not all(isinstance(v, str) for v in values):
            self.problem(cpath, "must be a string or an array of strings")
            return outer
        for v in values:
            if not (DTMI.match(v) and ";" in v):
                self.problem(cpath, f"{v!r} is not a DTMI with a version")
            elif v.startswith("dtmi:dtdl:context;") and v != self.language:
                self.problem(cpath, f"{v}: this checker knows DTDL v3 and v2, one a model")
            elif v not in KNOWN_CONTEXTS:
                self.problem(cpath, f"{v}: an extension this checker does not know")
        if top and self.language not in values:
            self.problem(cpath, f"must include {DTDL_V3_CONTEXT}")
        others = [v for v in values if not v.startswith("dtmi:dtdl:context;")]
        if (
            self.language in values
            and others
            and values.index(others[0]) < values.index(self.language)
        ):
            self.problem(cpath, f"{self.language} must come before the extensions")
        return [*outer, *values]

    def _id(self, value: Any, path: str, kind: str) -> None:
        if not isinstance(value, str) or not DTMI.match(value):
            self.problem(path, f"{value!r} is not a DTMI (dtmi:segment:segment;version)")
            return
        limit = INTERFACE_DTMI_MAX if kind == "Interface" else DTMI_MAX
        if len(value) > limit:
            self.problem(path, f"a {kind}'s DTMI has at most {limit} characters, not {len(value)}")
        if value.startswith(RESERVED_PREFIXES):
            self.problem(path, f"{value}: DTMIs starting dtmi:dtdl: or dtmi:standard: are reserved")
        if value in self.ids:
            self.problem(path, f"@id {value} is used twice (first at {self.ids[value]})")
        else:
            self.ids[value] = path

    def _name(self, value: Any, path: str) -> None:
        text = value.get("@value") if isinstance(value, dict) else value
        if not isinstance(text, str):
            self.problem(path, "must be a string")
        elif len(text) > (limit := V2_NAME_MAX if self.v2 else NAME_MAX):
            self.problem(path, f"at most {limit} characters, not {len(text)}")
        elif not NAME_PATTERN.match(text):
            self.problem(path, f"{text!r}: letters, digits and _, a letter first, not _ last")

    def _text(self, value: Any, path: str, limit: int, plain: bool) -> None:
        for text in element_texts(value, plain):
            if text is None:
                self.problem(path, "must be a string" + ("" if plain else " or a language map"))
            elif len(text) > limit:
                self.problem(path, f"at most {limit} characters, not {len(text)}")

    def _unique_name(self, node: Any, path: str, seen: dict[str, str], where: str) -> None:
        name = node.get("name") if isinstance(node, dict) else None
        if not isinstance(name, str):
            return
        if name in seen:
            self.problem(at(path, "name"), f"{name!r} is used twice in the {where} ({seen[name]})")
        else:
            seen[name] = path
