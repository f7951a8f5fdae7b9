"""twinlink's plain YAML form of a co-simulation, read into a System; errors give the line.

    instances:                      # name -> FMU (a path relative to this file, or lib:...)
      msd1.m1: MassSpringDamper1.fmu
      msd2.m2: lib:msd/MassSpringDamper2
      ctrl: {fmu: Controller.fmu, isolated: true}   # in a process of its own
      est: {fmu: Estimator.fmu, python_requirements: [filterpy==1.4.5]}  # ... with packages
    connections:                    # an output -> the inputs it feeds (a list, or one)
      msd1.m1.x1: [msd2.m2.x1]
      msd1.m1.v1: [msd2.m2.v1]
      msd2.m2.fk: msd1.m1.fk
    parameters:                     # a port -> its start value
      msd2.m2.c2: 1.0
    log:                            # an instance -> the variables recorded
      msd2.m2: [x2, v2]
    algorithm:
      type: fixed-step              # or var-step, with min_size and max_size
      size: 0.001                   # the step (var-step: the first step)
      master: gauss-seidel          # or jacobi
      # var-step only: tolerance (relative, 1e-3) and Maestro's constraints, e.g.
      # constraints: {sr: {type: samplingrate, base: -1, rate: 1, startTime: 0}}
    start_time: 0
    end_time: 10

A port is "instance.variable": the longest instance name it starts with is the instance, so
names may hold dots ("msd1.m1", Maestro's style) and so may variables ("der(x)", "a.b[1]").
`connections`, `parameters`, `log` and `start_time` may be left out; other keys are refused,
as a misspelt key would otherwise be lost without a word. `to_yaml` writes any System in this
form (a Maestro multi-model or an SSP converted), which reads back into the same System.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from twinlink.cosim import constraints as varstep_constraints
from twinlink.cosim.model import Algorithm, Connection, CosimFormatError, Instance, Port, System
from twinlink.domain.errors import DocumentError
from twinlink.domain.yamlsource import Path as YamlPath
from twinlink.domain.yamlsource import SourceDocument, dump_yaml, parse_yaml_stream
from twinlink.processors.fmuenv import requirement_problem

KEYS = frozenset(
    {"instances", "connections", "parameters", "log", "algorithm", "start_time", "end_time"}
)
INSTANCE_KEYS = frozenset({"fmu", "isolated", "python_requirements"})
ALGORITHM_KEYS = frozenset(
    {"type", "size", "min_size", "max_size", "master", "tolerance", "constraints"}
)

Scalar = float | int | bool | str


def read_yaml(source: Path | str, *, text: str | None = None) -> System:
    """The System the YAML file at `source` describes (or `text`, `source` then only its
    name in errors)."""
    name = str(source)
    if text is None:
        try:
            text = Path(source).read_text(encoding="utf-8")
        except OSError as err:
            raise CosimFormatError(f"{name}: cannot be read: {err.strerror or err}") from err
        except UnicodeDecodeError as err:
            raise CosimFormatError(f"{name}: is not UTF-8 text: {err.reason}") from err
    try:
        docs = parse_yaml_stream(text)
    except DocumentError as err:
        # the title speaks of storing a document; here only its problems matter
        problems = "; ".join(str(p) for p in err.problems) or err.title
        raise CosimFormatError(f"{name}: {problems}") from err
    if len(docs) != 1:
        raise CosimFormatError(f"{name}: holds {len(docs)} YAML documents; write one")
    return _Reader(name, docs[0]).system()


def from_mapping(data: Mapping[str, Any], name: str = "system") -> System:
    """The System `data` describes: the YAML form already parsed (JSON sent to the API, a
    processor's parameters). Errors name the key, as there are no lines; `name` starts them."""
    return _Reader(name, SourceDocument(data)).system()


def to_yaml(system: System) -> str:
    """`system` in the YAML form; read_yaml gives it back (its `source` then "yaml")."""
    connections: dict[str, list[str]] = {}
    for conn in system.connections:
        connections.setdefault(str(conn.source), []).append(str(conn.target))
    algorithm: dict[str, Any] = {"type": system.algorithm.kind, "size": system.algorithm.size}
    if system.algorithm.min_size is not None:
        algorithm["min_size"] = system.algorithm.min_size
    if system.algorithm.max_size is not None:
        algorithm["max_size"] = system.algorithm.max_size
    algorithm["master"] = system.algorithm.master
    if system.algorithm.tolerance is not None:
        algorithm["tolerance"] = system.algorithm.tolerance
    if system.algorithm.constraints:
        algorithm["constraints"] = {
            c.name: varstep_constraints.to_mapping(c) for c in system.algorithm.constraints
        }
    data: dict[str, Any] = {
        "instances": {i.name: _instance(i) for i in system.instances},
        "connections": connections,
        "parameters": {str(port): value for port, value in system.parameters.items()},
        "log": {name: list(names) for name, names in system.log_variables.items()},
        "algorithm": algorithm,
        "start_time": system.start_time,
    }
    if system.end_time is not None:
        data["end_time"] = system.end_time
    return dump_yaml(data)


def _instance(instance: Instance) -> str | dict[str, Any]:
    """An instance as the YAML form writes it: its FMU, or a mapping when it asks more."""
    if not instance.isolated:
        return instance.fmu
    out: dict[str, Any] = {"fmu": instance.fmu, "isolated": True}
    if instance.python_requirements:
        out["python_requirements"] = list(instance.python_requirements)
    return out


class _Reader:
    def __init__(self, name: str, doc: SourceDocument) -> None:
        self.name = name
        self.doc = doc
        self.names: list[str] = []  # longest first, for splitting ports

    def fail(self, path: YamlPath, problem: str) -> CosimFormatError:
        return CosimFormatError(f"{self.name}: {self.doc.problem(problem, path)}")

    def mapping(self, path: YamlPath, value: Any) -> Mapping[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(path, "is not a mapping")
        for key in value:
            if not isinstance(key, str):
                raise self.fail((*path, key), f"the key {key!r} is not a string")
        return value

    def port(self, path: YamlPath, text: Any) -> Port:
        if isinstance(text, str):
            for inst in self.names:
                if text.startswith(inst + ".") and len(text) > len(inst) + 1:
                    return Port(inst, text[len(inst) + 1 :])
        raise self.fail(path, f"{text!r} is not instance.variable of a declared instance")

    def system(self) -> System:
        data = self.mapping((), self.doc.data)
        for key in data:
            if key not in KEYS:
                raise self.fail((key,), f"unknown key; the keys are {', '.join(sorted(KEYS))}")
        if "instances" not in data or "algorithm" not in data:
            raise self.fail((), "instances and algorithm are required")
        instances = self._instances(data["instances"])
        self.names = sorted((i.name for i in instances), key=len, reverse=True)
        start = self._time(("start_time",), data.get("start_time", 0.0))
        end = None if data.get("end_time") is None else self._time(("end_time",), data["end_time"])
        if end is not None and end <= start:
            raise self.fail(("end_time",), f"{end} is not after start_time {start}")
        return System(
            instances=instances,
            connections=self._connections(data.get("connections") or {}),
            parameters=self._parameters(data.get("parameters") or {}),
            log_variables=self._log(data.get("log") or {}),
            algorithm=self._algorithm(data["algorithm"]),
            start_time=start,
            end_time=end,
            source="yaml",
        )

    def _instances(self, raw: Any) -> tuple[Instance, ...]:
        out = []
        for name, value in self.mapping(("instances",), raw).items():
            path: YamlPath = ("instances", name)
            fmu, isolated = value, False
            requirements: tuple[str, ...] = ()
            if isinstance(value, dict):  # {fmu: file, isolated: true, python_requirements: []}
                unknown = sorted(str(k) for k in set(value) - INSTANCE_KEYS)
                if unknown:
                    raise self.fail(
                        path,
                        f"has unknown keys ({', '.join(unknown)}); it takes fmu, isolated and "
                        "python_requirements",
                    )
                fmu, isolated = value.get("fmu"), value.get("isolated", False)
                if not isinstance(isolated, bool):
                    raise self.fail((*path, "isolated"), "is not true or false")
                requirements = self._requirements((*path, "python_requirements"), value)
            if not isinstance(fmu, str) or not fmu:
                raise self.fail(path, "is not an FMU path or lib: reference")
            # an environment of its own is a process of its own
            isolated = isolated or bool(requirements)
            out.append(Instance(name, fmu, isolated, requirements))
        if not out:
            raise self.fail(("instances",), "is empty")
        return tuple(out)

    def _requirements(self, path: YamlPath, entry: Mapping[str, Any]) -> tuple[str, ...]:
        raw = entry.get("python_requirements", [])
        if not isinstance(raw, list) or not all(isinstance(r, str) for r in raw):
            raise self.fail(path, 'is not a list of requirements ("name==version")')
        for i, line in enumerate(raw):
            if (problem := requirement_problem(line)) is not None:
                raise self.fail((*path, i), problem)
        return tuple(raw)

    def _connections(self, raw: Any) -> tuple[Connection, ...]:
        out: list[Connection] = []
        for src, targets in self.mapping(("connections",), raw).items():
            path: YamlPath = ("connections", src)
            source = self.port(path, src)
            items = targets if isinstance(targets, list) else [targets]
            out.extend(
                Connection(source, self.port((*path, i) if targets is items else path, t))
                for i, t in enumerate(items)
            )
        return tuple(out)

    def _parameters(self, raw: Any) -> dict[Port, Scalar]:
        out: dict[Port, Scalar] = {}
        for key, value in self.mapping(("parameters",), raw).items():
            path: YamlPath = ("parameters", key)
            if not isinstance(value, (bool, int, float, str)):
                raise self.fail(path, f"{value!r} is not a number, a Boolean or a string")
            if isinstance(value, float) and not math.isfinite(value):
                raise self.fail(path, f"{value} is not a finite number")
            out[self.port(path, key)] = value
        return out

    def _log(self, raw: Any) -> dict[str, tuple[str, ...]]:
        out: dict[str, tuple[str, ...]] = {}
        for inst, names in self.mapping(("log",), raw).items():
            if inst not in self.names:
                raise self.fail(("log", inst), "is not a declared instance")
            if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
                raise self.fail(("log", inst), "is not a list of variable names")
            out[inst] = tuple(names)
        return out

    def _time(self, path: YamlPath, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(path, f"{value!r} is not a time in seconds")
        try:
            seconds = float(value)
        except OverflowError:  # an integer too large for a float (JSON may hold one)
            raise self.fail(path, "is too large a time") from None
        if not math.isfinite(seconds):
            raise self.fail(path, f"{value} is not a finite time")
        return seconds

    def _step(self, path: YamlPath, value: Any) -> float:
        step = self._time(path, value)
        if step <= 0:
            raise self.fail(path, f"{value} is not a step size above 0")
        return step

    def _algorithm(self, raw: Any) -> Algorithm:
        data = self.mapping(("algorithm",), raw)
        for key in data:
            if key not in ALGORITHM_KEYS:
                keys = ", ".join(sorted(ALGORITHM_KEYS))
                raise self.fail(("algorithm", key), f"unknown key; the keys are {keys}")
        kind, master = data.get("type"), data.get("master", "gauss-seidel")
        if master not in ("jacobi", "gauss-seidel"):
            raise self.fail(
                ("algorithm", "master"), f'{master!r} is not "jacobi" or "gauss-seidel"'
            )
        size = self._step(("algorithm", "size"), data.get("size"))
        if kind == "fixed-step":
            for key in ("tolerance", "constraints"):
                if key in data:
                    raise self.fail(("algorithm", key), "applies to a var-step algorithm only")
            return Algorithm("fixed-step", size, master=master)
        if kind == "var-step":
            low = self._step(("algorithm", "min_size"), data.get("min_size", size))
            high = self._step(("algorithm", "max_size"), data.get("max_size", size))
            if not low <= size <= high:
                raise self.fail(("algorithm",), f"size {size} is not within [{low}, {high}]")
            tolerance = None
            if data.get("tolerance") is not None:
                tolerance = self._step(("algorithm", "tolerance"), data["tolerance"])
            constraints = varstep_constraints.parse(
                data.get("constraints"),
                "algorithm.constraints",
                lambda text, where: self.port(_path(where), text),
                lambda where, problem: self.fail(_path(where), problem),
            )
            return Algorithm(
                "var-step",
                size,
                min_size=low,
                max_size=high,
                master=master,
                tolerance=tolerance,
                constraints=constraints,
            )
        raise self.fail(("algorithm", "type"), f'{kind!r} is not "fixed-step" or "var-step"')


def _path(where: str) -> YamlPath:
    """ "algorithm.constraints.zc.ports" as the path to that node (for its line)."""
    return tuple(where.split("."))
