"""Which kind of instance runs an FMU: `open_slave` chooses.

A co-simulation FMU runs in this process (slaves.Slave). Model exchange and process
isolation come next (mexslave.py, isolated.py); until then every instance is a Slave.
"""

from __future__ import annotations

from pathlib import Path
from typing import cast

from .model import Instance
from .protocol import SlaveLike
from .slaves import Slave


def open_slave(instance: Instance, fmu_path: Path, workdir: Path) -> SlaveLike:
    """Open `instance` of the FMU at `fmu_path`, extracting it into `workdir`; raises
    CosimRunError naming the instance when the FMU cannot be used."""
    # cast until Slave has all of SlaveLike (step's time, FMU state: C1's slaves.py)
    return cast(SlaveLike, Slave(instance.name, fmu_path, workdir))
