"""What an `fmu` processor may ask of its FMU, checked against the FMU's description.

One code path for an FMU uploaded to the twin (`FmuRecord.info`) and a library FMU (the
description the library kept at push): both are `FmuInfo.as_dict()`. The rules follow the
FMI 2.0 and 3.0 standards on causality, variability and initial, and the value range of each
type, so a processor that would fail at its worker's start is refused when it is made (422,
naming the variable and the reason) instead of crash-looping in backoff.
"""

from __future__ import annotations

import math
from typing import Any

from twinlink.domain.errors import InvalidInputError

FLOAT_TYPES = frozenset({"Real", "Float64", "Float32"})
# The range each integer type can hold (FMI 2 Integer and Enumeration are fmi2Integer: int32;
# FMI 3 Enumeration is Int64). A value outside it would wrap around in the FMU (UInt8 300 -> 44).
INT_RANGES: dict[str, tuple[int, int]] = {
    "Integer": (-(2**31), 2**31 - 1),
    "Int8": (-(2**7), 2**7 - 1),
    "UInt8": (0, 2**8 - 1),
    "Int16": (-(2**15), 2**15 - 1),
    "UInt16": (0, 2**16 - 1),
    "Int32": (-(2**31), 2**31 - 1),
    "UInt32": (0, 2**32 - 1),
    "Int64": (-(2**63), 2**63 - 1),
    "UInt64": (0, 2**64 - 1),
}
FLOAT32_MAX = 3.4028234663852886e38
# Inputs the worker sets from live signals (converted from the signals' floats, range-checked
# with the out_of_range policy: blueprints/_fmu_io.py), and what it can write as outputs.
STREAMED_TYPES = FLOAT_TYPES | set(INT_RANGES) | {"Enumeration", "Boolean"}
OUTPUT_TYPES = STREAMED_TYPES


def check_fmu_params(
    params: dict[str, Any], mapped: list[str], info: dict[str, Any], where: str
) -> None:
    """Refuse `params` (an fmu processor's) and `mapped` (the keys of its `inputs`) that the
    FMU described by `info` cannot run with: InvalidInputError naming the variable and why."""
    fmi3 = str(info.get("fmi_version", "2.0")).startswith("3")
    by_name = {str(v.get("name")): v for v in info.get("variables", [])}
    _known(params, by_name, where)
    wanted = params.get("inputs")
    if wanted is not None:
        bad = [_why_not_streamed(by_name[n]) for n in wanted]
        _refuse("inputs", [f"{n}: {why}" for n, why in zip(wanted, bad, strict=True) if why])
        streamed = list(wanted)
    else:
        streamed = [n for n, v in by_name.items() if _why_not_streamed(v) is None]
    unknown = [k for k in mapped if k not in streamed]
    if unknown:
        raise InvalidInputError(
            f"inputs: {', '.join(unknown)} is not an input the processor streams into "
            f"{where} (it streams: {', '.join(streamed) or 'none'}); check the spelling"
        )
    outputs = params.get("outputs") or []
    _refuse("outputs", [f"{n}: {why}" for n in outputs if (why := _why_not_output(by_name[n]))])
    problems = []
    for name, value in (params.get("parameters") or {}).items():
        var = by_name[name]
        why = _why_not_settable(var, fmi3) or value_problem(var, value, fmi3)
        if why:
            problems.append(f"{name}: {why}")
    _refuse("parameters", problems)


def _known(params: dict[str, Any], by_name: dict[str, Any], where: str) -> None:
    asked = {
        "inputs": params.get("inputs") or [],
        "outputs": params.get("outputs") or [],
        "parameters": list(params.get("parameters") or {}),
    }
    for what, wanted in asked.items():
        unknown = [n for n in wanted if n not in by_name]
        if unknown:
            names = sorted(by_name)
            valid = ", ".join(names[:20]) + (" ..." if len(names) > 20 else "")
            raise InvalidInputError(
                f"params.{what}: {where} has no variable {', '.join(unknown)} (it has: {valid})"
            )


def _refuse(what: str, problems: list[str]) -> None:
    if problems:
        raise InvalidInputError(f"params.{what}: " + "; ".join(problems))


def _why_not_streamed(var: dict[str, Any]) -> str | None:
    if var.get("causality") != "input":
        return f"it is not an input (causality {var.get('causality')})"
    if var.get("shape"):
        return "it is an array; only scalar inputs can be streamed"
    if var.get("type") not in STREAMED_TYPES:
        return f"it is of type {var.get('type')}, which a live signal cannot be set into"
    return None


def _why_not_output(var: dict[str, Any]) -> str | None:
    if var.get("shape"):
        return "it is an array; only scalar variables can be outputs"
    if var.get("type") not in OUTPUT_TYPES:
        return f"it is of type {var.get('type')}; outputs must be numbers or booleans"
    return None


def _why_not_settable(var: dict[str, Any], fmi3: bool) -> str | None:
    """Why the FMI standard forbids setting `var` before initialization, if it does.

    FMI 2 (table in section 2.2.7) and FMI 3 (section 2.4.7.4): inputs, and variables with
    initial exact or approx that are not constants, may be given a start value; constants,
    calculated parameters, independent variables and calculated outputs or locals may not.
    """
    causality, variability = var.get("causality"), var.get("variability")
    if variability == "constant":
        return "it is a constant"
    if causality in {"calculatedParameter", "independent"}:
        return f"it is {'an' if causality == 'independent' else 'a'} {causality}"
    if causality == "structuralParameter":
        return "it is a structural parameter (set in configuration mode, not supported)"
    if var.get("type") in {"Binary", "Clock"}:
        return f"variables of type {var.get('type')} cannot be set"
    if var.get("shape"):
        return "it is an array; only scalar variables can be set"
    if causality == "input" or var.get("initial") in {"exact", "approx"}:
        return None
    return f"it is calculated by the FMU ({causality}, initial {var.get('initial')})"


def value_problem(var: dict[str, Any], value: Any, fmi3: bool) -> str | None:
    """Why `value` does not fit the type and declared range of `var`, if it does not."""
    type_ = str(var.get("type"))
    if type_ == "Boolean":
        ok = isinstance(value, bool) or (
            isinstance(value, str) and value.strip().lower() in {"true", "false"}
        )
        return None if ok else f"{value!r} is not a Boolean: give true or false"
    if type_ == "String":
        return None if isinstance(value, str) else f"{value!r} is not a string"
    if type_ == "Enumeration":
        return _enumeration_problem(var, value, fmi3)
    if type_ not in FLOAT_TYPES and type_ not in INT_RANGES:
        return f"variables of type {type_} cannot be set"
    if isinstance(value, bool) or not isinstance(value, int | float):
        return f"{value!r} is not a number ({type_})"
    if type_ in FLOAT_TYPES:
        if not math.isfinite(value):
            return f"{value!r} is not a finite number"
        if type_ == "Float32" and abs(value) > FLOAT32_MAX:
            return f"{value!r} is outside the range of Float32"
        return _range_problem(var, value, type_)
    if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
        return f"{value!r} is not a whole number ({type_})"
    low, high = INT_RANGES[type_]
    if not low <= int(value) <= high:
        return f"{int(value)} is outside the range of {type_} [{low}, {high}]"
    return _range_problem(var, int(value), type_)


def _enumeration_problem(var: dict[str, Any], value: Any, fmi3: bool) -> str | None:
    items = {str(i["name"]): int(i["value"]) for i in var.get("items") or []}
    if isinstance(value, str) and value in items:
        return None
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        named = ", ".join(f"{n} ({v})" for n, v in items.items())
        return f"{value!r} is not an item of the enumeration" + (f": {named}" if named else "")
    if items and value not in items.values():
        named = ", ".join(f"{n} ({v})" for n, v in items.items())
        return f"{value} is not an item of the enumeration: {named}"
    low, high = INT_RANGES["Int64" if fmi3 else "Integer"]
    if not low <= value <= high:
        return f"{value} is outside the range of an enumeration [{low}, {high}]"
    return None


def enumeration_value(var: dict[str, Any], value: Any) -> Any:
    """An enumeration item given by name as its value; anything else as it is."""
    items = {str(i["name"]): int(i["value"]) for i in var.get("items") or []}
    return items.get(value, value) if isinstance(value, str) else value


def _range_problem(var: dict[str, Any], value: float, type_: str) -> str | None:
    low, high = var.get("min"), var.get("max")
    if (low is not None and value < low) or (high is not None and value > high):
        span = f"[{'' if low is None else f'{low:g}'}, {'' if high is None else f'{high:g}'}]"
        return f"{value!r} is outside its declared range {span}"
    return None
