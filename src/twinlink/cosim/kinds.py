"""Which kind of instance runs an FMU: `open_slave` chooses.

- a co-simulation FMU runs in this process (slaves.Slave), stepped by its own doStep;
- a model exchange FMU (one without a co-simulation binary) runs in this process under
  FMPy's solvers (mexslave.MeSlave);
- a Python FMU (pythonfmu), or an instance the file asks to isolate, runs in a process of
  its own (isolated.IsolatedSlave): two Python FMUs in one process share one interpreter
  and break each other, and a crash of an isolated FMU fails the run, not the process.

An instance with `python_requirements` runs in a process whose Python is a virtualenv with
those packages, built once per list by processors/fmuenv.py (as a processor's
python_requirements are) under `envs_root()`: $TWINLINK_FMU_ENVS_DIR, else the user's cache
folder (~/.cache/twinlink/fmu-envs). Building one takes pip's time, the first time only.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import os
import zipfile
from collections.abc import Coroutine
from pathlib import Path
from typing import Any, Literal, TypeVar

from twinlink.processors.fmuenv import EnvBuildError, FmuEnvs
from twinlink.processors.fmuinfo import FmuError, FmuInfo, inspect_fmu

from .isolated import IsolatedSlave
from .mexslave import MeSlave
from .model import Instance
from .protocol import SlaveLike
from .slaves import CosimRunError, Slave

Kind = Literal["co-simulation", "model-exchange", "python"]
# pythonfmu writes the module of the model's class here; no other tool does.
PYTHONFMU_MARKER = "resources/slavemodule.txt"
ENVS_DIR_VAR = "TWINLINK_FMU_ENVS_DIR"  # where the instances' Python environments are kept
_T = TypeVar("_T")


def is_python_fmu(fmu_path: Path) -> bool:
    """Whether the FMU was built by pythonfmu (its archive holds resources/slavemodule.txt)."""
    try:
        with zipfile.ZipFile(fmu_path) as archive:
            names = archive.namelist()
    except (OSError, zipfile.BadZipFile):
        return False  # not an FMU at all: inspect_fmu says why
    return PYTHONFMU_MARKER in names


def kind_of(info: FmuInfo, fmu_path: Path) -> Kind:
    """How an FMU runs in a co-simulation: "python" (pythonfmu: a process of its own),
    "co-simulation" (its doStep) or "model-exchange" (FMPy's solvers)."""
    if is_python_fmu(fmu_path):
        return "python"
    cs, me = info.interface("CoSimulation"), info.interface("ModelExchange")
    if me is not None and me.has_binary and not (cs is not None and cs.has_binary):
        return "model-exchange"
    return "co-simulation"  # or none usable here: Slave says which binary is missing


def open_slave(instance: Instance, fmu_path: Path, workdir: Path) -> SlaveLike:
    """Open `instance` of the FMU at `fmu_path`, extracting it into `workdir`; raises
    CosimRunError naming the instance when the FMU cannot be used."""
    if instance.python_requirements:
        python = python_env(instance)
        return IsolatedSlave(instance.name, fmu_path, workdir, python=str(python))
    if instance.isolated or is_python_fmu(fmu_path):
        return IsolatedSlave(instance.name, fmu_path, workdir)
    return open_in_process(instance.name, fmu_path, workdir)


def open_in_process(name: str, fmu_path: Path, workdir: Path) -> Slave:
    """A Slave or MeSlave in this process (an isolated instance's child opens its FMU so)."""
    try:
        info = inspect_fmu(fmu_path)
    except FmuError as err:
        raise CosimRunError(f"instance {name!r} ({fmu_path.name}): {err}") from err
    if kind_of(info, fmu_path) == "model-exchange":
        return MeSlave(name, fmu_path, workdir)
    return Slave(name, fmu_path, workdir)


def envs_root() -> Path:
    """Where the instances' Python environments are built and kept."""
    configured = os.environ.get(ENVS_DIR_VAR)
    if configured:
        return Path(configured)
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "twinlink" / "fmu-envs"


def python_env(instance: Instance) -> Path:
    """The interpreter of the environment with `instance`'s python_requirements, built first
    if need be; CosimRunError naming the instance, with pip's last lines, if it cannot be."""
    requirements = list(instance.python_requirements)
    try:
        return _run(FmuEnvs(envs_root()).python(requirements))
    except EnvBuildError as err:
        raise CosimRunError(
            f"instance {instance.name!r}: its Python environment ({', '.join(requirements)}) "
            f"could not be built: {err}"
        ) from err


def _run(coroutine: Coroutine[Any, Any, _T]) -> _T:
    """Run `coroutine` to its end from synchronous code, also from a thread whose event loop
    is running (the cosim processor's): then in a thread of its own."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return asyncio.run(coroutine)
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        return pool.submit(asyncio.run, coroutine).result()
