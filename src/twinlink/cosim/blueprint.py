"""The `cosim` blueprint: a co-simulation run beside live data (mode 3), in a processor.

Some FMU inputs come from the processor's input signals (a twin's measured streams), some
FMU variables go out as its output signals: a plant model and an estimator beside the
measurements. The system is twinlink's YAML form given as a mapping (docs/cosim.md), its FMUs
named by the file names of FMUs uploaded to the twin.

Time 0 of the co-simulation (its `start_time`) is the first sample's timestamp. Each batch
steps the Session on the algorithm's grid up to the batch's last sample, holding the latest
value of each input (as the FMU blueprint's fixed mode does: a sample's values are set for
the step in which it falls), and gives one output sample per communication point, the first
at time 0. An FMU that ends the simulation, or the system's `end_time` reached, finishes the
processor (`finished`, not restarted).

Runs in the processor's worker, a process of its own: a crashing FMU takes down the worker,
which the supervisor restarts from a fresh Session (time 0 again at the next sample).
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, field_validator

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.samples import SIGNAL_NAME
from twinlink.processors.blueprint import Batch, Blueprint, BlueprintError, Context, Params
from twinlink.processors.blueprints._fmu_io import InputGuard
from twinlink.processors.fmuinfo import FmuError, FmuInfo, FmuVariable, inspect_fmu

from ._livefeed import Feed, typed
from .model import Port, System
from .results import column_name
from .session import Session
from .yamlform import from_mapping

# As the twin's FMU store names its uploads (processors/fmus.py, not imported: server side).
FMU_FILE = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}\.fmu$")
LIBRARY = "lib:"


class CosimParams(Params):
    system: dict[str, Any] = Field(
        description="The co-simulation in twinlink's YAML form (docs/cosim.md) as a mapping: "
        "instances (name -> the file name of an FMU uploaded to the twin), connections, "
        "parameters, log, algorithm, start_time, end_time."
    )
    inputs: dict[str, str] = Field(
        default_factory=dict,
        description="input signal -> the FMU input it feeds, instance.variable (an input no "
        "connection feeds); it holds the signal's latest value.",
    )
    outputs: dict[str, str] = Field(
        description="output signal -> the FMU variable it carries, instance.variable; one "
        "sample per communication point."
    )
    out_of_range: Literal["clamp", "reject"] = Field(
        "clamp",
        description="Input values outside the FMU input's declared min/max (or its type's "
        "range): clamp, or skip the sample.",
    )

    @field_validator("inputs", "outputs")
    @classmethod
    def _signal_names(cls, value: dict[str, str]) -> dict[str, str]:
        bad = [name for name in value if not SIGNAL_NAME.match(name)]
        if bad:
            raise ValueError(f"{', '.join(map(repr, bad))} is not a signal name")
        return value

    @field_validator("outputs")
    @classmethod
    def _some_output(cls, value: dict[str, str]) -> dict[str, str]:
        if not value:
            raise ValueError("name at least one output signal and the variable it carries")
        return value


def checked_system(params: CosimParams) -> tuple[System, dict[str, Port], dict[str, Port]]:
    """The system the params describe, and the port of each input and output signal; a
    BlueprintError names the key that is wrong. Reads no file: the FMUs are checked when
    the worker opens them."""
    try:
        system = from_mapping(params.system, "system")
    except TwinlinkError as err:
        raise BlueprintError(str(err)) from err
    for instance in system.instances:
        if instance.fmu.startswith(LIBRARY):
            raise BlueprintError(
                f"system: instances.{instance.name}: library FMUs ({instance.fmu}) are not "
                "supported in a processor yet; upload the FMU to the twin and name its file"
            )
        if not FMU_FILE.match(instance.fmu):
            raise BlueprintError(
                f"system: instances.{instance.name}: {instance.fmu!r} is not the file name of "
                "an FMU uploaded to the twin (letters, digits, '_', '.', '-', ending .fmu)"
            )
    names = sorted((i.name for i in system.instances), key=len, reverse=True)
    inputs = {s: _port(names, "inputs", s, text) for s, text in params.inputs.items()}
    outputs = {s: _port(names, "outputs", s, text) for s, text in params.outputs.items()}
    fed = {c.target for c in system.connections}
    wired = [f"{signal} ({port})" for signal, port in inputs.items() if port in fed]
    if wired:
        raise BlueprintError(
            f"inputs: {', '.join(wired)}: a connection of the system feeds it; map signals "
            "only to inputs no connection feeds"
        )
    twice = sorted({str(p) for p in inputs.values() if list(inputs.values()).count(p) > 1})
    if twice:
        raise BlueprintError(f"inputs: {', '.join(twice)} is fed by two signals; keep one")
    return system, inputs, outputs


def _port(names: Sequence[str], key: str, signal: str, text: str) -> Port:
    """`text` as instance.variable, the longest declared instance name it starts with being
    the instance (as the YAML form splits its ports)."""
    for name in names:
        if text.startswith(name + ".") and len(text) > len(name) + 1:
            return Port(name, text[len(name) + 1 :])
    raise BlueprintError(
        f"{key}.{signal}: {text!r} is not instance.variable of an instance of the system "
        f"(the instances: {', '.join(sorted(names))})"
    )


def logged(system: System, ports: Sequence[Port]) -> System:
    """`system` also recording `ports`, so each output is a column of the Session's rows."""
    log = {name: list(variables) for name, variables in system.log_variables.items()}
    for port in ports:
        variables = log.setdefault(port.instance, [])
        if port.variable not in variables:
            variables.append(port.variable)
    return dataclasses.replace(system, log_variables={k: tuple(v) for k, v in log.items()})


class CosimBlueprint(Blueprint[CosimParams]):
    """Runs a co-simulation of several FMUs beside live data: input signals feed FMU
    inputs, FMU variables go out as output signals (docs/cosim.md)."""

    name = "cosim"
    title = "Co-simulation"
    Params = CosimParams

    def __init__(self, params: CosimParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._system, self._in, self._out = checked_system(params)
        self._session: Session | None = None
        self._feed: Feed | None = None
        self._guard: InputGuard | None = None
        self._types: list[str] = []

    @classmethod
    def check(cls, params: Any) -> None:
        checked_system(params)

    @classmethod
    def uploads(cls, params: Any) -> dict[str, dict[str, str]]:
        system, inputs, outputs = checked_system(params)
        named: list[tuple[Port, str]] = [(p, f"inputs.{s} ({p})") for s, p in inputs.items()]
        named += [(p, f"outputs.{s} ({p})") for s, p in outputs.items()]
        for c in system.connections:
            named += [(port, f"system: connections ({port})") for port in (c.source, c.target)]
        named += [(p, f"system: parameters.{p}") for p in system.parameters]
        for name, variables in system.log_variables.items():
            named += [(Port(name, v), f"system: log.{name} ({name}.{v})") for v in variables]
        fmus = {i.name: i.fmu for i in system.instances}
        wanted: dict[str, dict[str, str]] = {fmu: {} for fmu in fmus.values()}
        for port, key in named:
            wanted[fmus[port.instance]].setdefault(port.variable, key)
        return wanted

    def inputs(self) -> list[str]:
        return list(self.params.inputs)

    def outputs(self) -> list[str]:
        return list(self.params.outputs)

    def describe(self) -> dict[str, Any]:
        system = self._system
        algorithm = system.algorithm
        d: dict[str, Any] = {
            "instances": {i.name: i.fmu for i in system.instances},
            "connections": [[str(c.source), str(c.target)] for c in system.connections],
            "algorithm": {
                "type": algorithm.kind,
                "size": algorithm.size,
                "master": algorithm.master,
            },
            "start_time": system.start_time,
            "end_time": system.end_time,
            "inputs": {s: str(p) for s, p in self._in.items()},
            "outputs": {s: str(p) for s, p in self._out.items()},
        }
        session, guard = self._session, self._guard
        if session is not None and guard is not None:
            counts = dict(zip(guard.names, guard.counts, strict=True))
            d["state"] = {
                "time_s": session.time,
                "steps": session.steps,
                "clamped" if self.params.out_of_range == "clamp" else "rejected": counts,
                "skipped_samples": guard.skipped,
            }
        return d

    def start(self) -> None:
        files = Path(self.ctx.files)
        missing = [i for i in self._system.instances if not (files / i.fmu).is_file()]
        if missing:
            raise BlueprintError(
                "the twin has no uploaded FMU "
                + ", ".join(f"{i.fmu!r} (instance {i.name})" for i in missing)
                + "; upload it first (PUT /api/v1/twins/{twin}/fmus/{name})"
            )
        variables, fmi3 = self._typed_inputs(files)
        system = logged(self._system, list(self._out.values()))
        paths = {i.fmu: files / i.fmu for i in system.instances}
        ports = list(dict.fromkeys(self._in.values()))
        try:
            # In the worker's workdir, which each start empties: a killed worker's
            # extracted FMUs do not pile up.
            Path(self.ctx.workdir).mkdir(parents=True, exist_ok=True)
            session = Session(system, paths, external_inputs=ports, workdir=self.ctx.workdir)
        except TwinlinkError as err:
            raise BlueprintError(f"the co-simulation cannot start: {err}") from err
        self._session = session
        try:
            columns = [session.columns.index(column_name(system, p)) for p in self._out.values()]
        except ValueError as err:  # not reached: `logged` records every output
            self.stop()
            raise BlueprintError(f"an output is not recorded: {err}") from err
        self._feed = Feed(session, system, list(self._in.values()), columns)
        # As the FMU blueprint's inputs: clamped (or the sample rejected) to the variable's
        # range, reported as events; NaN holds (before a first value: the start value).
        held = [math.nan] * len(variables)
        self._guard = InputGuard(variables, held, self.params.out_of_range, self.ctx, fmi3)
        self._types = [v.type for v in variables]

    def _typed_inputs(self, files: Path) -> tuple[list[FmuVariable], bool]:
        """Each input's FMU variable, named by its port (for events), and whether all their
        FMUs are FMI 3 (an Enumeration without items then ranges over Int64)."""
        fmus = {i.name: i.fmu for i in self._system.instances}
        infos: dict[str, FmuInfo] = {}
        variables = []
        for signal, port in self._in.items():
            fmu = fmus[port.instance]
            if fmu not in infos:
                try:
                    infos[fmu] = inspect_fmu(files / fmu)
                except FmuError as err:
                    raise BlueprintError(f"{fmu} (instance {port.instance}): {err}") from err
            found = [v for v in infos[fmu].variables if v.name == port.variable]
            if not found:
                raise BlueprintError(f"inputs.{signal}: {fmu} has no variable {port.variable!r}")
            variables.append(dataclasses.replace(found[0], name=str(port)))
        fmi3 = bool(infos) and all(i.fmi_version.startswith("3") for i in infos.values())
        return variables, fmi3

    def process(self, batch: Batch) -> Batch | None:
        feed, session, guard = self._feed, self._session, self._guard
        if feed is None or session is None or guard is None:
            raise BlueprintError("the co-simulation is not started")
        times = batch.times
        if len(times) > 1 and bool(np.any(times[1:] < times[:-1])):
            batch = batch.take(np.argsort(times, kind="stable"))
        times, u = guard.condition(batch.times, [batch.columns.get(s) for s in self._in])
        if not len(times):
            return None
        typed(u, self._types)
        try:
            times, rows = feed.run(times, u)
        except TwinlinkError as err:  # a failed FMU: this worker cannot go on with it
            raise BlueprintError(str(err)) from err
        if feed.ended:
            self.ctx.finish(feed.ended, sim_time_s=session.time)
        if not len(times):
            return None
        return Batch(times, {s: rows[:, c] for s, c in zip(self._out, feed.columns, strict=True)})

    def stop(self) -> None:
        session, self._session, self._feed, self._guard = self._session, None, None, None
        if session is not None:
            session.close()
