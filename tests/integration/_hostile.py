"""A small fuzzer of numbers for the API, driven by a real server's /openapi.json: every
numeric path and query parameter, every numeric field of a JSON body model, and numbers put
into the free-form bodies (documents, settings, configs) through a seed body per route.

A route that takes a free-form body or a body model with numbers and has no seed here makes
the test fail by name, so a new route cannot slip past it."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

# Text for path and query parameters: beyond int64 and uint64, beyond a double, not numbers,
# an int Python refuses to parse (over 4 300 digits), and plain wrong signs and fractions.
QUERY_VALUES = [
    "9223372036854775808",
    "-9223372036854775809",
    "18446744073709551616",
    "1e400",
    "-1e400",
    "nan",
    "inf",
    "-inf",
    "1e10",
    "1e300",
    "-1",
    "0",
    "1.5",
    "9" * 5000,
]
# Times and durations that routes take as text (ns, ISO 8601, `-1d`, a bucket, a cursor): the
# numbers above, and dates and durations past what int64 ns hold.
TIME_PARAMETERS = {"start", "end", "bucket", "cursor", "since", "until", "at"}
TIME_VALUES = [
    *QUERY_VALUES,
    "9223372036854775807",
    "-9223372036854775808",
    "9999-12-31T23:59:59Z",
    "0001-01-01",
    "1000-01-01T00:00:00Z",
    "99999999999999999999d",
    "-99999999999999999999d",
    "1e300s",
    "-1e300s",
    "nand",
    "P99999999Y",
    "9223372036854775807:9223372036854775807",
]
# JSON literals for bodies (`NaN` and `Infinity` are not JSON, and Python's reader takes them).
BIG_INTS = ["9223372036854775808", "-9223372036854775809", str(2**80), "9" * 4000]
BODY_VALUES = [*BIG_INTS, "1e400", "NaN", "Infinity", "1e10", "1e18", "1e300", "-1", "0", "1.5"]
HOLE = "@"  # where a seed body takes the value


@dataclass(frozen=True)
class Operation:
    method: str
    path: str  # the OpenAPI template, /api/v1/twins/{slug}/...
    spec: dict[str, Any]


def operations(doc: dict[str, Any]) -> Iterator[Operation]:
    for path, ops in doc["paths"].items():
        for method, spec in ops.items():
            yield Operation(method.upper(), path, spec)


def resolve(doc: dict[str, Any], schema: dict[str, Any]) -> dict[str, Any]:
    ref = schema.get("$ref")
    if ref is None:
        return schema
    return doc["components"]["schemas"][ref.rsplit("/", 1)[-1]]  # type: ignore[no-any-return]


def numeric(doc: dict[str, Any], schema: dict[str, Any]) -> dict[str, Any] | None:
    """The number schema within `schema` (itself, or the number of an `anyOf` with null)."""
    schema = resolve(doc, schema)
    if schema.get("type") in ("integer", "number"):
        return schema
    for option in schema.get("anyOf", []):
        found = numeric(doc, option)
        if found is not None:
            return found
    return None


def numeric_parameters(doc: dict[str, Any], op: Operation) -> list[tuple[str, str, dict[str, Any]]]:
    """(where, name, number schema) of each numeric path or query parameter."""
    out = []
    for param in op.spec.get("parameters", []):
        found = numeric(doc, param.get("schema", {}))
        if found is not None:
            out.append((param["in"], param["name"], found))
    return out


def time_parameters(op: Operation) -> list[str]:
    """Names of the query parameters that take a time or a duration as text."""
    return [
        p["name"]
        for p in op.spec.get("parameters", [])
        if p["in"] == "query" and p["name"] in TIME_PARAMETERS
    ]


def body_schema(doc: dict[str, Any], op: Operation) -> dict[str, Any] | None:
    content = op.spec.get("requestBody", {}).get("content", {})
    if "application/json" not in content:
        return None
    return resolve(doc, content["application/json"].get("schema", {}))


def numeric_fields(
    doc: dict[str, Any], schema: dict[str, Any], path: tuple[str, ...] = ()
) -> Iterator[tuple[tuple[str, ...], dict[str, Any], str]]:
    """(path, number schema, model name) of each numeric field of a body model, nested
    models included (not the free-form parts: those get seeds)."""
    title = schema.get("title", "")
    for name, prop in schema.get("properties", {}).items():
        found = numeric(doc, prop)
        if found is not None:
            yield (*path, name), found, title
            continue
        inner = resolve(doc, prop)
        options = [resolve(doc, o) for o in prop.get("anyOf", [])] or [inner]
        for option in options:
            if option.get("properties"):
                yield from numeric_fields(doc, option, (*path, name))


def is_free_form(schema: dict[str, Any]) -> bool:
    return schema.get("type") == "object" and not schema.get("properties")


def has_range(schema: dict[str, Any]) -> bool:
    low = "minimum" in schema or "exclusiveMinimum" in schema
    high = "maximum" in schema or "exclusiveMaximum" in schema
    return low and high


def with_value(base: dict[str, Any], path: tuple[str | int, ...]) -> str:
    """`base` as JSON text with HOLE at `path` (keys, and indexes into lists `base` holds),
    to be replaced by a raw JSON literal."""
    body = json.loads(json.dumps(base))
    node = body
    for key in path[:-1]:
        node = node[key] if isinstance(key, int) else node.setdefault(key, {})
    node[path[-1]] = HOLE
    return json.dumps(body).replace(f'"{HOLE}"', HOLE)


def schema_numbers(
    root: dict[str, Any], schema: dict[str, Any], base: Any, path: tuple[str | int, ...] = ()
) -> Iterator[tuple[str | int, ...]]:
    """Paths of the numeric fields of a JSON schema (with local $defs, as in blueprint
    parameters and connector configs) that `base` reaches: its own properties, and those of
    the first item of a list of objects it holds."""
    if "$ref" in schema:
        schema = root["$defs"][schema["$ref"].rsplit("/", 1)[-1]]
    for option in schema.get("anyOf", []):
        yield from schema_numbers(root, option, base, path)
    if schema.get("type") in ("integer", "number"):
        yield path
    elif schema.get("type") == "array" and isinstance(base, list) and base:
        yield from schema_numbers(root, schema.get("items", {}), base[0], (*path, 0))
    elif isinstance(base, dict):
        for name, prop in schema.get("properties", {}).items():
            yield from schema_numbers(root, prop, base.get(name), (*path, name))


def schema_at(root: dict[str, Any], path: tuple[str | int, ...]) -> dict[str, Any]:
    """The number schema at `path` (as `schema_numbers` gives it) of a JSON schema."""
    schema = root
    for key in path:
        schema = _number_or_self(root, schema)
        schema = schema["items"] if isinstance(key, int) else schema["properties"][key]
    return _number_or_self(root, schema)


def _number_or_self(root: dict[str, Any], schema: dict[str, Any]) -> dict[str, Any]:
    if "$ref" in schema:
        schema = root["$defs"][schema["$ref"].rsplit("/", 1)[-1]]
    for option in schema.get("anyOf", []):
        if "$ref" in option or option.get("type") in ("integer", "number", "object", "array"):
            return _number_or_self(root, option)
    return schema


def fill_path(template: str, names: dict[str, str]) -> str:
    """A concrete path: each {param} from `names` (by the collection before it, then by
    name), the numeric ones left for the caller."""

    def one(match: re.Match[str]) -> str:
        name = match.group(1)
        before = template[: match.start()].rstrip("/").rsplit("/", 1)[-1]
        return names.get(f"{before}/{name}", names.get(name, match.group(0)))

    return re.sub(r"\{([^}]+)\}", one, template)
