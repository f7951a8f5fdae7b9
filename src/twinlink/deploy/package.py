"""twin.yaml: a twin package's description, read with the line of every value, and its
parameters checked against the package's JSON Schema.

A package is refused whole, with every problem found and its line, before anything of it is
used: unknown top-level keys (a typo would otherwise be a part silently not deployed), lists
that are not lists, resources without a name or with one name twice.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass, field
from typing import Any

from jsonschema import Draft202012Validator  # type: ignore[import-untyped]
from jsonschema.exceptions import SchemaError  # type: ignore[import-untyped]

from twinlink.domain.errors import DocumentError, InvalidInputError, Problem
from twinlink.domain.yamlsource import SourceDocument, parse_yaml_stream

PACKAGE_FILE = "twin.yaml"
PHASES = ("create", "execute", "analyze", "evolve", "save", "terminate", "clean")
KINDS = ("devices", "processors", "connectors", "services")
TOP_KEYS = (
    "description", "parameters", "assets", "document", *KINDS, "lifecycle", "runner_tags",
)  # fmt: skip
ALIAS = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]{0,63}$")
REFUSED = "The twin package's twin.yaml has problems; nothing was deployed."


@dataclass(frozen=True, slots=True)
class PhaseLimits:
    """A phase's limits as twin.yaml gives them. None: not given there, so the package's
    `default`, then the server's settings (run_default_timeout_s, run_default_memory_mb)
    decide (deploy/runs.py's RunTarget.limits)."""

    timeout_s: int | None = None  # 0: runs until the deployment is stopped
    memory_mb: int | None = None


@dataclass(slots=True)
class Package:
    """A parsed twin.yaml; `source` keeps the lines its values came from."""

    source: SourceDocument
    description: str = ""
    parameters: dict[str, Any] | None = None  # a JSON Schema of an object
    assets: dict[str, str] = field(default_factory=dict)  # alias -> library ref
    document: str | dict[str, Any] | None = None  # a file of the package, or the document
    devices: list[dict[str, Any]] = field(default_factory=list)
    processors: list[dict[str, Any]] = field(default_factory=list)
    connectors: list[dict[str, Any]] = field(default_factory=list)
    services: list[dict[str, Any]] = field(default_factory=list)
    lifecycle: dict[str, PhaseLimits] = field(default_factory=dict)
    runner_tags: list[str] = field(default_factory=list)

    def limits(self, phase: str) -> PhaseLimits:
        """The limits the package gives a lifecycle phase: each its own, else the package's
        `default`; None where neither gives it (the server's setting then)."""
        given = self.lifecycle.get(phase, PhaseLimits())
        default = self.lifecycle.get("default", PhaseLimits())
        return PhaseLimits(
            default.timeout_s if given.timeout_s is None else given.timeout_s,
            default.memory_mb if given.memory_mb is None else given.memory_mb,
        )


def parse_package(text: str) -> Package:
    """The package twin.yaml describes; DocumentError lists every problem with its line."""
    docs = parse_yaml_stream(text)
    if len(docs) != 1 or not isinstance(docs[0].data, dict):
        raise DocumentError(REFUSED, [Problem("twin.yaml must be one YAML mapping")])
    src = docs[0]
    data: dict[str, Any] = src.data
    problems: list[Problem] = []
    unknown = [k for k in data if k not in TOP_KEYS]
    for key in unknown:
        problems.append(src.problem(f"unknown key {key!r}; a twin.yaml has {', '.join(TOP_KEYS)}",
                                    (str(key),)))  # fmt: skip
    package = Package(source=src)
    description = data.get("description", "")
    if not isinstance(description, str):
        problems.append(src.problem("description is text", ("description",)))
    else:
        package.description = description
    package.parameters = _schema(src, data.get("parameters"), problems)
    package.assets = _assets(src, data.get("assets"), problems)
    document = data.get("document")
    if document is not None and not isinstance(document, str | dict):
        problems.append(src.problem("document is a file of the package or a mapping",
                                    ("document",)))  # fmt: skip
    else:
        package.document = document
    for kind in KINDS:
        setattr(package, kind, _resources(src, kind, data.get(kind), problems))
    package.lifecycle = _lifecycle(src, data.get("lifecycle"), problems)
    tags = data.get("runner_tags", [])
    if not isinstance(tags, list) or not all(isinstance(t, str) and t for t in tags):
        problems.append(src.problem("runner_tags is a list of tag names", ("runner_tags",)))
    else:
        package.runner_tags = tags
    if problems:
        raise DocumentError(REFUSED, problems)
    return package


def _schema(src: SourceDocument, schema: Any, problems: list[Problem]) -> dict[str, Any] | None:
    if schema is None:
        return None
    if not isinstance(schema, dict):
        problems.append(src.problem("parameters is a JSON Schema (a mapping)", ("parameters",)))
        return None
    try:
        Draft202012Validator.check_schema(schema)
    except SchemaError as err:
        path = ("parameters", *(str(p) for p in err.path))
        problems.append(src.problem(f"not a valid JSON Schema: {err.message}", path))
        return None
    if schema.get("type", "object") != "object":
        problems.append(src.problem("parameters is the schema of an object (type: object)",
                                    ("parameters", "type")))  # fmt: skip
        return None
    return schema


def _assets(src: SourceDocument, assets: Any, problems: list[Problem]) -> dict[str, str]:
    if assets is None:
        return {}
    if not isinstance(assets, dict):
        problems.append(src.problem("assets maps names to library refs", ("assets",)))
        return {}
    out = {}
    for alias, ref in assets.items():
        if not isinstance(alias, str) or not ALIAS.match(alias):
            problems.append(src.problem(f"asset name {alias!r}: letters, digits, _ and -",
                                        ("assets", str(alias))))  # fmt: skip
        elif not isinstance(ref, str) or not ref:
            problems.append(src.problem("a library ref, as lib:models/NAME@VERSION",
                                        ("assets", alias)))  # fmt: skip
        else:
            out[alias] = ref
    return out


def _resources(
    src: SourceDocument, kind: str, items: Any, problems: list[Problem]
) -> list[dict[str, Any]]:
    if items is None:
        return []
    if not isinstance(items, list):
        problems.append(src.problem(f"{kind} is a list", (kind,)))
        return []
    seen: set[str] = set()
    for i, item in enumerate(items):
        name = item.get("name") if isinstance(item, dict) else None
        if not isinstance(item, dict):
            problems.append(src.problem(f"each of {kind} is a mapping", (kind, i)))
        elif not isinstance(name, str) or not name:
            problems.append(src.problem(f"each of {kind} needs a `name`", (kind, i)))
        elif name in seen:
            problems.append(src.problem(f"{name!r} is named twice in {kind}", (kind, i, "name")))
        else:
            seen.add(name)
        if kind == "devices" and isinstance(item, dict):
            extra = set(item) - {"name", "description"}
            if extra:
                problems.append(src.problem(f"a device has a name and a description, not "
                                            f"{sorted(extra)}", (kind, i)))  # fmt: skip
    return items


def _lifecycle(
    src: SourceDocument, lifecycle: Any, problems: list[Problem]
) -> dict[str, PhaseLimits]:
    if lifecycle is None:
        return {}
    if not isinstance(lifecycle, dict):
        problems.append(src.problem("lifecycle maps phases to their limits", ("lifecycle",)))
        return {}
    out = {}
    for phase, limits in lifecycle.items():
        path = ("lifecycle", str(phase))
        if phase != "default" and phase not in PHASES:
            problems.append(src.problem(f"unknown phase {phase!r}; phases: default, "
                                        f"{', '.join(PHASES)}", path))  # fmt: skip
            continue
        if not isinstance(limits, dict) or set(limits) - {"timeout_s", "memory_mb"}:
            problems.append(src.problem("a phase has timeout_s and memory_mb", path))
            continue
        timeout = limits.get("timeout_s")
        memory = limits.get("memory_mb")
        if (timeout is not None and not _whole(timeout, 0)) or (
            memory is not None and not _whole(memory, 1)
        ):
            problems.append(src.problem("timeout_s is a whole number of seconds (0: none), "
                                        "memory_mb a whole number of MiB", path))  # fmt: skip
            continue
        out[phase] = PhaseLimits(timeout, memory)
    return out


def _whole(value: Any, least: int) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= least


def checked_parameters(schema: dict[str, Any] | None, given: Any) -> dict[str, Any]:
    """The parameters with the schema's defaults filled in; InvalidInputError names the first
    parameter that does not fit the schema, and what is wrong with it."""
    if given is None:
        given = {}
    if not isinstance(given, dict):
        raise InvalidInputError("`parameters` is a JSON object of the package's parameters")
    if schema is None:
        if given:
            raise InvalidInputError(
                f"the package takes no parameters, but {sorted(given)} were given"
            )
        return {}
    params = copy.deepcopy(given)
    with_defaults(schema, params)
    errors = sorted(Draft202012Validator(schema).iter_errors(params), key=lambda e: list(e.path))
    if errors:
        first = errors[0]
        where = ".".join(str(p) for p in first.path)
        if not where and first.validator == "additionalProperties":
            raise InvalidInputError(f"parameters: {first.message}")
        if not where and first.validator == "required":
            raise InvalidInputError(f"parameters: {first.message}")
        raise InvalidInputError(f"parameter {where or '(all)'}: {first.message}")
    return params


def with_defaults(schema: dict[str, Any], value: dict[str, Any]) -> None:
    """Fill in `value` the defaults of the schema's properties that it lacks, in nested objects
    too."""
    properties = schema.get("properties")
    if not isinstance(properties, dict):
        return
    for name, sub in properties.items():
        if not isinstance(sub, dict):
            continue
        if name not in value and "default" in sub:
            value[name] = copy.deepcopy(sub["default"])
        if isinstance(value.get(name), dict):
            with_defaults(sub, value[name])
