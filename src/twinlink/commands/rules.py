"""What a twin's `interface` allows for commands and properties, and the checks that apply it.

A twin whose interface declares no `commands` accepts any command name and any JSON arguments;
one that declares commands accepts only those, with arguments checked against `parameters`.
Likewise for `properties`: when declared, a desired value must name a writable property and
fit its type and range; a reported value must name a declared property and fit its type.
Every refusal raises `InvalidInputError` with a reason a person can act on.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import orjson

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.jsontext import first_big_int, int64_problem

NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.:-]{0,127}$")
MAX_STRING = 1024
MAX_ARGS_BYTES = 64 * 1024
_INT_LIMIT = 1 << 63
_TYPES = ("number", "integer", "bool", "string")


@dataclass(slots=True, frozen=True)
class ValueRule:
    name: str
    type: str = "number"
    min: float | None = None
    max: float | None = None
    required: bool = False
    default: Any = None
    writable: bool = False


@dataclass(slots=True, frozen=True)
class Rules:
    """The commands (name -> parameters) and properties a twin declares; empty: anything goes."""

    commands: dict[str, dict[str, ValueRule]] = field(default_factory=dict)
    properties: dict[str, ValueRule] = field(default_factory=dict)


OPEN_RULES = Rules()


def rules_from_interface(interface: Any) -> Rules:
    if not isinstance(interface, dict):
        return OPEN_RULES
    commands: dict[str, dict[str, ValueRule]] = {}
    for command in interface.get("commands") or []:
        if isinstance(command, dict) and isinstance(command.get("name"), str):
            params = [_rule(p) for p in command.get("parameters") or [] if _named(p)]
            commands[command["name"]] = {p.name: p for p in params}
    properties = {
        p.name: p for p in (_rule(x) for x in interface.get("properties") or [] if _named(x))
    }
    return Rules(commands, properties)


def _named(item: Any) -> bool:
    return isinstance(item, dict) and isinstance(item.get("name"), str)


def _rule(raw: dict[str, Any]) -> ValueRule:
    kind = raw.get("type", "number")
    return ValueRule(
        name=raw["name"],
        type=kind if kind in _TYPES else "number",
        min=raw.get("min"),
        max=raw.get("max"),
        required=bool(raw.get("required", False)),
        default=raw.get("default"),
        writable=bool(raw.get("writable", False)),
    )


# -- commands --------------------------------------------------------------------------------


def check_command(rules: Rules, name: Any, args: Any) -> dict[str, Any]:
    """The arguments to send (defaults filled in), or InvalidInputError saying what is wrong."""
    check_name(name, "command ")
    if args is None:
        args = {}
    if not isinstance(args, dict):
        raise InvalidInputError("`args` must be a JSON object of argument name -> value")
    # Before anything writes them: orjson cannot, and a device could not read them.
    big = first_big_int(args, "args")
    if big is not None:
        raise InvalidInputError(f"{name}: {big[0]}: {int64_problem(big[1])}")
    if len(orjson.dumps(args)) > MAX_ARGS_BYTES:
        raise InvalidInputError(f"`args` may hold at most {MAX_ARGS_BYTES} bytes of JSON")
    if not rules.commands:
        return dict(args)
    params = rules.commands.get(name)
    if params is None:
        known = ", ".join(sorted(rules.commands))
        raise InvalidInputError(f"the twin has no command {name!r}; its commands are: {known}")
    unknown = sorted(set(args) - set(params))
    if unknown:
        takes = ", ".join(params) or "no arguments"
        raise InvalidInputError(f"{name}: unknown argument {unknown[0]!r}; it takes {takes}")
    out: dict[str, Any] = {}
    for param in params.values():
        if param.name in args:
            check_value(param, args[param.name], ranged=True, where=f"{name}: argument ")
            out[param.name] = args[param.name]
        elif param.required:
            raise InvalidInputError(f"{name}: the argument {param.name!r} is required")
        elif param.default is not None:
            out[param.name] = param.default
    return out


# -- values ----------------------------------------------------------------------------------


def check_name(name: Any, where: str = "") -> None:
    if not isinstance(name, str) or not NAME.match(name):
        raise InvalidInputError(f"{where}name {name!r} must match {NAME.pattern}")


def check_plain(name: Any, value: Any, where: str = "") -> None:
    """A property value: a finite number, a bool or a string of at most 1 024 characters."""
    check_name(name, where)
    kind = type(value)
    if kind is float and not math.isfinite(value):
        raise InvalidInputError(f"{where}{name}: {value} is not a finite number")
    if kind is int and not -_INT_LIMIT <= value < _INT_LIMIT:
        raise InvalidInputError(f"{where}{name}: {int64_problem(value)}")
    if kind is str and len(value) > MAX_STRING:
        raise InvalidInputError(f"{where}{name}: a string holds at most {MAX_STRING} characters")
    if kind not in (float, int, str, bool):
        raise InvalidInputError(f"{where}{name}: {_show(value)} is not a number, bool or string")


def check_value(rule: ValueRule, value: Any, ranged: bool, where: str = "") -> None:
    kind = type(value)
    label = f"{where}{rule.name!r}"
    if rule.type == "number" and kind not in (int, float):
        raise InvalidInputError(f"{label}: {_show(value)} is not a number")
    if rule.type == "integer" and kind is not int:
        raise InvalidInputError(f"{label}: {_show(value)} is not an integer")
    if rule.type == "bool" and kind is not bool:
        raise InvalidInputError(f"{label}: {_show(value)} is not a bool (true or false)")
    if rule.type == "string" and kind is not str:
        raise InvalidInputError(f"{label}: {_show(value)} is not a string")
    if kind is float and not math.isfinite(value):
        raise InvalidInputError(f"{label}: {value} is not a finite number")
    if ranged and kind in (int, float):
        if rule.min is not None and value < rule.min:
            raise InvalidInputError(f"{label}: {value} is below the minimum {rule.min}")
        if rule.max is not None and value > rule.max:
            raise InvalidInputError(f"{label}: {value} is above the maximum {rule.max}")


# -- properties ------------------------------------------------------------------------------


def check_desired(rules: Rules, changes: Any) -> dict[str, Any]:
    """Desired values to set; `None` removes one. Checked against declared properties."""
    if not isinstance(changes, dict) or not changes:
        raise InvalidInputError("the body must be a JSON object of property name -> value")
    for name, value in changes.items():
        if value is None:  # removes the desired value
            check_name(name, "desired ")
            continue
        check_plain(name, value, "desired ")
        if not rules.properties:
            continue
        rule = rules.properties.get(name)
        if rule is None:
            known = ", ".join(sorted(rules.properties))
            raise InvalidInputError(f"the twin has no property {name!r}; its properties: {known}")
        if not rule.writable:
            raise InvalidInputError(f"the property {name!r} is not writable (set by the device)")
        check_value(rule, value, ranged=True, where="desired ")
    return dict(changes)


def check_reported(rules: Rules, properties: Any) -> dict[str, Any]:
    if not isinstance(properties, dict) or not properties:
        raise InvalidInputError("`properties` must be an object of at least one name -> value")
    for name, value in properties.items():
        check_plain(name, value, "reported ")
        if rules.properties:
            rule = rules.properties.get(name)
            if rule is None:
                raise InvalidInputError(f"reported {name!r}: not a property of this twin")
            check_value(rule, value, ranged=False, where="reported ")
    return dict(properties)


def _show(value: Any) -> str:
    text = orjson.dumps(value).decode() if _jsonable(value) else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _jsonable(value: Any) -> bool:
    try:
        orjson.dumps(value)
    except TypeError:
        return False
    return True
