"""What a run records when its file names nothing: every output a row can hold.

An SSP archive has no list of variables to record (Maestro's `logVariables`, the YAML form's
`log`), and a run recording only the time would be of no use; so every scalar output of every
instance is recorded, as FMPy's simulate_ssp does. The CLI and the server's runs both go
through here, so the same file gives the same columns wherever it runs.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from twinlink.processors.fmuinfo import FmuError, inspect_fmu

from .model import System

UNRECORDED = frozenset({"String", "Binary", "Clock"})  # a row holds numbers only


def every_output(system: System, fmu_paths: Mapping[str, Path]) -> System:
    """`system` itself when it records something; else the same system recording every
    scalar output of every instance (not String, Binary or Clock: a row holds numbers)."""
    if system.log_variables:
        return system
    recorded: dict[str, tuple[str, ...]] = {}
    for instance in system.instances:
        path = fmu_paths.get(instance.fmu)
        if path is None:
            continue  # the run names the instance without an FMU
        try:
            info = inspect_fmu(Path(path))
        except FmuError:
            continue  # the run names the FMU and why it cannot be used
        outputs = tuple(
            v.name
            for v in info.variables
            if v.causality == "output" and not v.shape and v.type not in UNRECORDED
        )
        if outputs:
            recorded[instance.name] = outputs
    return replace(system, log_variables=recorded)
