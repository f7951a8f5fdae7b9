"""`twinlink cosim check`: what a co-simulation file holds, as a person reads it, and its
algebraic loops found from the FMUs' own feedthrough (ModelStructure dependencies)."""

from __future__ import annotations

from collections.abc import Mapping

import fmpy  # type: ignore[import-untyped]

from twinlink.cli.cosimrun import Loaded
from twinlink.cosim.graph import algebraic_loops, describe_loop, feedthrough_of
from twinlink.cosim.kinds import kind_of
from twinlink.cosim.model import Port
from twinlink.cosim.reading import unapplied
from twinlink.processors.fmuinfo import FmuError, inspect_fmu


def describe(loaded: Loaded) -> tuple[list[str], list[list[Port]]]:
    """The lines to print, and the algebraic loops (an FMU that cannot be read counts as
    feeding every input through to every output, so no loop is missed)."""
    system = loaded.system
    lines = [f"{loaded.path}: a co-simulation ({_FORMATS.get(system.source, system.source)})"]
    lines.append(f"instances ({len(system.instances)}):")
    feedthrough: dict[str, Mapping[str, set[str]] | None] = {}
    for instance in system.instances:
        path = loaded.fmu_paths[instance.fmu]
        try:
            info = inspect_fmu(path)
        except FmuError as err:
            kind = f"cannot be used: {err}"
            feedthrough[instance.name] = None
        else:
            kind = f"{kind_of(info, path)}, FMI {info.fmi_version}"
            md = fmpy.read_model_description(str(path), validate=False)
            feedthrough[instance.name] = feedthrough_of(md)
        isolated = ", isolated" if instance.isolated else ""
        lines.append(f"  {instance.name}  {instance.fmu}  ({kind}{isolated})")
    lines.append(f"connections ({len(system.connections)}):")
    lines += [f"  {c.source} -> {c.target}" for c in system.connections]
    if system.parameters:
        lines.append(f"parameters ({len(system.parameters)}):")
        lines += [f"  {port} = {value!r}" for port, value in system.parameters.items()]
    recorded = [f"{i}.{v}" for i, names in system.log_variables.items() for v in names]
    every = ", every output: the file names none" if loaded.every_output else ""
    lines.append(f"recorded ({len(recorded)}{every}): {', '.join(recorded) or 'none'}")
    lines.append(f"algorithm: {_algorithm(loaded)}")
    lines += [f"  {note}" for note in unapplied(loaded.path)]
    loops = algebraic_loops(system, feedthrough.get)
    if loops:
        lines.append(f"algebraic loops ({len(loops)}):")
        lines += [f"  {describe_loop(loop)}" for loop in loops]
    else:
        lines.append("algebraic loops: none")
    return lines, loops


_FORMATS = {"maestro": "Maestro multi-model", "ssp": "SSP archive", "yaml": "YAML form"}


def _algorithm(loaded: Loaded) -> str:
    system, a = loaded.system, loaded.system.algorithm
    if a.kind == "var-step":
        low, high = a.min_size or a.size, a.max_size or a.size
        step = f"var-step from {a.size:g} s, between {low:g} and {high:g} s"
    else:
        step = f"fixed-step {a.size:g} s"
    end = "open end" if system.end_time is None else f"to {system.end_time:g} s"
    return f"{step}, {a.master}, from {system.start_time:g} s {end}"
