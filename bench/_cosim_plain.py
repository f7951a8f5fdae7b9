"""The reference for bench/cosim.py: the same FMUs driven by FMPy's FMU2Slave in a plain
Python loop, the best a user would write by hand for one system (value references looked up
once, one getReal/setReal per instance and step, the values in a flat list, a row a step
appended), in the same stepping order and with the same exchange as twinlink's master.
"""

from __future__ import annotations

import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fmpy import extract, read_model_description  # type: ignore[import-untyped]
from fmpy.fmi2 import FMU2Slave  # type: ignore[import-untyped]

from twinlink.cosim.master import stepping_order
from twinlink.cosim.model import System


@dataclass
class _Unit:
    """One instance: its FMU2Slave, its inputs' value references and where in the flat
    list of values their sources are, its outputs' value references and slots."""

    fmu: Any
    unzipdir: str
    vrs: dict[str, int]
    in_vrs: list[int] = field(default_factory=list)
    in_from: list[int] = field(default_factory=list)
    out_vrs: list[int] = field(default_factory=list)
    out_at: list[int] = field(default_factory=list)


class PlainLoop:
    """`system` opened with FMPy, initialized with the connections exchanged once (as
    twinlink's Session does), ready for `run`."""

    def __init__(self, system: System, fmu_paths: dict[str, Path]) -> None:
        by_name = {i.name: i for i in system.instances}
        self.order = stepping_order(system)
        self.jacobi = system.algorithm.master == "jacobi"
        self.h = system.algorithm.size
        self.t0 = system.start_time
        self.units: list[_Unit] = []
        descriptions: dict[str, Any] = {}
        slots: dict[tuple[str, str], int] = {}  # an output's place in the flat list

        def slot(instance: str, variable: str) -> int:
            return slots.setdefault((instance, variable), len(slots))

        for name in self.order:
            path = str(fmu_paths[by_name[name].fmu])
            md = descriptions.get(path) or read_model_description(path, validate=False)
            descriptions[path] = md
            vrs = {v.name: v.valueReference for v in md.modelVariables}
            unzipdir = extract(path)
            fmu = FMU2Slave(
                guid=md.guid,
                unzipDirectory=unzipdir,
                modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName=name,
            )
            unit = _Unit(fmu, unzipdir, vrs)
            for c in system.connections:
                if c.target.instance == name:
                    unit.in_vrs.append(vrs[c.target.variable])
                    unit.in_from.append(slot(c.source.instance, c.source.variable))
            outputs = [c.source.variable for c in system.connections if c.source.instance == name]
            outputs += list(system.log_variables.get(name, ()))
            for variable in dict.fromkeys(outputs):
                unit.out_vrs.append(vrs[variable])
                unit.out_at.append(slot(name, variable))
            self.units.append(unit)
        self.values = [0.0] * len(slots)
        self.recorded = [
            slots[(instance, variable)]
            for instance, variables in system.log_variables.items()
            for variable in variables
        ]
        self._initialize(system)

    def _initialize(self, system: System) -> None:
        for name, unit in zip(self.order, self.units, strict=True):
            unit.fmu.instantiate()
            unit.fmu.setupExperiment(startTime=self.t0)
            for port, value in system.parameters.items():
                if port.instance == name:
                    unit.fmu.setReal([unit.vrs[port.variable]], [float(value)])
            unit.fmu.enterInitializationMode()
        for unit in self.units:
            self._set(unit)
            self._get(unit)
        for unit in self.units:
            unit.fmu.exitInitializationMode()

    def _set(self, unit: _Unit) -> None:
        if unit.in_vrs:
            values = self.values
            unit.fmu.setReal(unit.in_vrs, [values[i] for i in unit.in_from])

    def _get(self, unit: _Unit) -> None:
        values = self.values
        for i, v in zip(unit.out_at, unit.fmu.getReal(unit.out_vrs), strict=True):
            values[i] = v

    def run(self, steps: int) -> tuple[float, list[list[float]]]:
        """Take `steps` macro steps; the wall seconds they took and the rows. The loop is
        written out as a user would, without a helper call per instance."""
        rows: list[list[float]] = []
        values, recorded, units, h, t0 = self.values, self.recorded, self.units, self.h, self.t0
        begin = time.perf_counter()
        for k in range(steps):
            t = t0 + k * h
            if self.jacobi:
                inputs = [[values[i] for i in unit.in_from] for unit in units]
                for unit, given in zip(units, inputs, strict=True):
                    if given:
                        unit.fmu.setReal(unit.in_vrs, given)
                    unit.fmu.doStep(t, h)
                for unit in units:
                    for i, v in zip(unit.out_at, unit.fmu.getReal(unit.out_vrs), strict=True):
                        values[i] = v
            else:
                for unit in units:
                    if unit.in_vrs:
                        unit.fmu.setReal(unit.in_vrs, [values[i] for i in unit.in_from])
                    unit.fmu.doStep(t, h)
                    for i, v in zip(unit.out_at, unit.fmu.getReal(unit.out_vrs), strict=True):
                        values[i] = v
            rows.append([t0 + (k + 1) * h, *[values[i] for i in recorded]])
        return time.perf_counter() - begin, rows

    def close(self) -> None:
        for unit in self.units:
            unit.fmu.terminate()
            unit.fmu.freeInstance()
            shutil.rmtree(unit.unzipdir, ignore_errors=True)
