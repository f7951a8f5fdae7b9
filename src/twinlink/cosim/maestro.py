"""Maestro's (INTO-CPS) multi-model JSON read into a System, files written by the tools as
they are.

A multi-model names its FMUs by key (`"fmus": {"{msd1}": "MassSpringDamper1.fmu"}`) and its
ports as "{key}.instance.variable": `connections` map an output to the list of inputs it
feeds, `parameters` a port to its start value, `logVariables` "{key}.instance" to the
variables recorded. The co-simulation settings (`algorithm`, `startTime`, `endTime`, ...) are
in the same JSON (Maestro 2's single file) or in a second one (the INTO-CPS app's coe.json,
Maestro 1's `--configuration` beside the multi-model): `settings` takes that one, its keys
completing or overriding the multi-model's.

An instance "m1" of the FMU "{msd1}" is named "msd1.m1". FMU paths stay as written, relative
to the document's folder. Maestro's masters are Jacobi (every FMU steps from the outputs of
the step before), so a multi-model's algorithm is a Jacobi one. Keys this reader does not
use (`simulationProgramDelay`, `liveGraphs`, `overrideLogLevel`, ...) are ignored, never an
error: files from newer tools still load. A var-step algorithm's `constraints` are read
(constraints.py applies them); `global_absolute_tolerance` and `global_relative_tolerance`
are Maestro's tolerances for stabilisation (iterating a step until coupled values settle),
which twinlink's masters do not do, so they are not the var-step tolerance.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from twinlink.cosim import constraints as varstep_constraints
from twinlink.cosim.model import Algorithm, Connection, CosimFormatError, Instance, Port, System

# "{key}.instance.variable": a variable name may hold dots ("der(x.y)", "body.frame.r[1]"),
# a key and an instance name do not (Maestro splits them the same way).
_PORT = re.compile(r"^\{([^{}]+)\}\.([^.]+)\.(.+)$")
_INSTANCE = re.compile(r"^\{([^{}]+)\}\.([^.]+)$")

Scalar = float | int | bool | str


class _Reader:
    """One multi-model being read: its name for errors and the instances seen so far."""

    def __init__(self, name: str, fmus: Mapping[str, str]) -> None:
        self.name = name
        self.fmus = fmus
        self.instances: dict[str, Instance] = {}

    def fail(self, key: str, problem: str) -> CosimFormatError:
        return CosimFormatError(f"{self.name}: {key}: {problem}")

    def instance(self, key: str, inst: str, where: str) -> str:
        braced = "{" + key + "}"
        if braced not in self.fmus:
            known = ", ".join(sorted(self.fmus)) or "none"
            raise self.fail(where, f"the FMU {braced} is not in fmus (known: {known})")
        name = f"{key}.{inst}"
        self.instances.setdefault(name, Instance(name=name, fmu=self.fmus[braced]))
        return name

    def port(self, text: Any, where: str) -> Port:
        m = _PORT.match(text) if isinstance(text, str) else None
        if m is None:
            raise self.fail(where, f'{text!r} is not a port; write "{{fmu}}.instance.variable"')
        return Port(self.instance(m[1], m[2], where), m[3])


def _load(source: Path | str | Mapping[str, Any], what: str) -> tuple[dict[str, Any], str]:
    if isinstance(source, Mapping):
        return dict(source), what
    path = Path(source)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise CosimFormatError(f"{path}: cannot be read: {err.strerror or err}") from err
    except UnicodeDecodeError as err:
        raise CosimFormatError(f"{path}: is not UTF-8 text: {err.reason}") from err
    except json.JSONDecodeError as err:
        raise CosimFormatError(
            f"{path}: is not valid JSON: {err.msg} at line {err.lineno}, column {err.colno}"
        ) from err
    if not isinstance(data, dict):
        raise CosimFormatError(f"{path}: is not a JSON object (a multi-model is one)")
    return data, str(path)


def read_maestro(
    source: Path | str | Mapping[str, Any],
    base_dir: Path | None = None,
    *,
    settings: Path | str | Mapping[str, Any] | None = None,
) -> System:
    """The System a multi-model describes: `source` is its file or its parsed JSON,
    `settings` the co-simulation configuration when it is a file of its own. `base_dir`
    (the document's folder, the file's own by default) resolves a relative `settings` path;
    FMU paths stay relative to it."""
    if base_dir is None and not isinstance(source, Mapping):
        base_dir = Path(source).parent
    data, name = _load(source, "the multi-model")
    if settings is not None:
        if not isinstance(settings, Mapping) and base_dir is not None:
            settings = base_dir / settings
        extra, extra_name = _load(settings, "the settings")
        data = _merge(data, extra)
        name = f"{name} (with {extra_name})"
    reader = _Reader(name, _fmus(data, name))
    connections = _connections(reader, data.get("connections", {}))
    parameters = _parameters(reader, data.get("parameters", {}))
    log_variables = _log_variables(reader, data.get("logVariables", {}))
    start = _time(reader, data, "startTime", 0.0)
    end = _time(reader, data, "endTime", None)
    if end is None:  # the legacy COE's spelling, as in Maestro's own test files
        end = _time(reader, data, "end_time", None)
    if end is not None and start is not None and end <= start:
        raise reader.fail("endTime", f"{end} is not after startTime {start}")
    return System(
        instances=tuple(reader.instances.values()),
        connections=connections,
        parameters=parameters,
        log_variables=log_variables,
        algorithm=_algorithm(reader, data.get("algorithm")),
        start_time=start if start is not None else 0.0,
        end_time=end,
        source="maestro",
    )


def _merge(model: dict[str, Any], settings: Mapping[str, Any]) -> dict[str, Any]:
    """The multi-model completed by its settings. The INTO-CPS app's coe.json holds
    `parameters` and `logVariables` of its own (often `{}`): those add to the multi-model's
    (a parameter given in both takes the settings' value, the variables logged are both
    lists), every other key of the settings replaces the multi-model's."""
    out = {**model, **settings}
    params, extra_params = model.get("parameters"), settings.get("parameters")
    if isinstance(params, dict) and isinstance(extra_params, dict):
        out["parameters"] = {**params, **extra_params}
    logs, extra_logs = model.get("logVariables"), settings.get("logVariables")
    if isinstance(logs, dict) and isinstance(extra_logs, dict):
        merged = dict(logs)
        for key, names in extra_logs.items():
            known = merged.get(key)
            if isinstance(known, list) and isinstance(names, list):
                names = known + [n for n in names if n not in known]
            merged[key] = names
        out["logVariables"] = merged
    return out


def _fmus(data: Mapping[str, Any], name: str) -> dict[str, str]:
    fmus = data.get("fmus")
    if not isinstance(fmus, dict) or not fmus:
        raise CosimFormatError(
            f'{name}: fmus: missing or empty; write {{"fmus": {{"{{key}}": "file.fmu"}}}}'
        )
    for key, path in fmus.items():
        if not (key.startswith("{") and key.endswith("}") and len(key) > 2):
            raise CosimFormatError(f'{name}: fmus: the key {key!r} is not written "{{key}}"')
        if not isinstance(path, str) or not path:
            raise CosimFormatError(f"{name}: fmus.{key}: {path!r} is not a file path")
    return fmus


def _connections(reader: _Reader, raw: Any) -> tuple[Connection, ...]:
    if not isinstance(raw, dict):
        raise reader.fail("connections", "is not an object of output -> [inputs]")
    out: list[Connection] = []
    for src, targets in raw.items():
        where = f"connections.{src}"
        source = reader.port(src, where)
        if not isinstance(targets, list):
            raise reader.fail(where, "is not a list of inputs")
        out.extend(Connection(source, reader.port(t, where)) for t in targets)
    return tuple(out)


def _parameters(reader: _Reader, raw: Any) -> dict[Port, Scalar]:
    if not isinstance(raw, dict):
        raise reader.fail("parameters", "is not an object of port -> value")
    out: dict[Port, Scalar] = {}
    for key, value in raw.items():
        where = f"parameters.{key}"
        if not isinstance(value, (bool, int, float, str)):
            raise reader.fail(where, f"{value!r} is not a number, a Boolean or a string")
        if isinstance(value, float) and not math.isfinite(value):
            raise reader.fail(where, f"{value} is not a finite number")
        out[reader.port(key, where)] = value
    return out


def _log_variables(reader: _Reader, raw: Any) -> dict[str, tuple[str, ...]]:
    if not isinstance(raw, dict):
        raise reader.fail("logVariables", 'is not an object of "{fmu}.instance" -> [variables]')
    out: dict[str, tuple[str, ...]] = {}
    for key, names in raw.items():
        where = f"logVariables.{key}"
        m = _INSTANCE.match(key)
        if m is None:
            raise reader.fail(where, f'{key!r} is not an instance; write "{{fmu}}.instance"')
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise reader.fail(where, "is not a list of variable names")
        out[reader.instance(m[1], m[2], where)] = tuple(names)
    return out


def _time(reader: _Reader, data: Mapping[str, Any], key: str, default: float | None) -> Any:
    value = data.get(key, default)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise reader.fail(key, f"{value!r} is not a time in seconds")
    return float(value)


def _positive(reader: _Reader, value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise reader.fail(where, f"{value!r} is not a step size in seconds above 0")
    if not math.isfinite(value):
        raise reader.fail(where, f"{value!r} is not a finite step size")
    return float(value)


def _algorithm(reader: _Reader, raw: Any) -> Algorithm:
    if raw is None:
        raise reader.fail(
            "algorithm",
            'missing; write {"type": "fixed-step", "size": 0.001} here or in the settings',
        )
    if not isinstance(raw, dict):
        raise reader.fail("algorithm", "is not an object")
    kind = raw.get("type")
    if kind == "fixed-step":
        return Algorithm(
            "fixed-step", _positive(reader, raw.get("size"), "algorithm.size"), master="jacobi"
        )
    if kind == "var-step":
        bounds = raw.get("size")
        if not isinstance(bounds, list) or len(bounds) != 2:
            raise reader.fail("algorithm.size", "is not [min, max] for a var-step algorithm")
        low = _positive(reader, bounds[0], "algorithm.size[0]")
        high = _positive(reader, bounds[1], "algorithm.size[1]")
        init = _positive(reader, raw.get("initsize", low), "algorithm.initsize")
        if not low <= init <= high:
            raise reader.fail("algorithm", f"initsize {init} is not within size [{low}, {high}]")
        constraints = varstep_constraints.parse(
            raw.get("constraints"), "algorithm.constraints", reader.port, reader.fail
        )
        return Algorithm(
            "var-step", init, min_size=low, max_size=high, master="jacobi", constraints=constraints
        )
    raise reader.fail("algorithm.type", f'{kind!r} is neither "fixed-step" nor "var-step"')
