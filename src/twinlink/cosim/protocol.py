"""What a master needs of an FMU instance, whatever runs it: a co-simulation FMU in this
process (slaves.Slave), a model exchange FMU under FMPy's solvers (mexslave.py), or an FMU
in a process of its own (isolated.py). `open_slave` (kinds.py) chooses.

The master exchanges values through the Groups' numpy buffers: `read` fills the output
buffers from the FMU, `write` sends the input buffers to it.
"""

from __future__ import annotations

from typing import Protocol

from twinlink.processors.fmuinfo import FmuInfo, Scalar

from .slaves import Group


class SlaveLike(Protocol):
    name: str  # the instance's name in the system
    label: str  # "instance 'msd1.m1' (msd1.fmu)", for messages
    info: FmuInfo
    can_rollback: bool  # save_state/restore_state work (FMI 2 canGetAndSetFMUstate, FMI 3)

    def port(self, name: str, *, into: bool) -> tuple[Group, int]: ...

    def bind(self) -> None: ...

    def set_start_values(self, values: list[tuple[str, Scalar]]) -> None: ...

    def enter_initialization(self, start: float, stop: float | None) -> None: ...

    def exit_initialization(self) -> None: ...

    def read(self) -> None: ...

    def write(self) -> None: ...

    def step(self, t: float, h: float) -> float:
        """Step from t by h; the time reached (t + h, or less after an FMI 3 early return
        or an fmi2Discard without termination). Raises FmuTerminated, CosimRunError."""
        ...

    def save_state(self) -> object: ...

    def restore_state(self, state: object) -> None: ...

    def free_state(self, state: object) -> None: ...

    def close(self) -> None: ...
