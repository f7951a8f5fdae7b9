"""The co-simulation model every format reads into: FMU instances, the connections between
their ports, start values, what to record, and the master algorithm with its time span.

A Maestro multi-model (maestro.py), an SSP archive (ssp.py) and twinlink's YAML form
(yamlform.py) all become one `System`, so the checks (graph.py) and the masters see one shape
whatever the file was. Everything is frozen: a System read once is shared, never changed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from twinlink.domain.errors import InvalidInputError


@dataclass(frozen=True, slots=True)
class Port:
    """One variable of one instance: "{key}.instance.var" in Maestro, (component,
    connector) in SSP. A Maestro instance "inst" of the FMU "{msd1}" is written
    Port(instance="msd1.inst", ...), the key without its braces."""

    instance: str
    variable: str

    def __str__(self) -> str:
        return f"{self.instance}.{self.variable}"


@dataclass(frozen=True, slots=True)
class Instance:
    """An instance of an FMU. `name` is unique in the system ("msd1.m1" in Maestro, the
    component's name in SSP); `fmu` a file path relative to the document's folder (or inside
    the SSP archive) or a `lib:` reference to the library. `isolated` asks for a process of
    its own (Python FMUs always get one: two in one process break each other);
    `python_requirements` runs that process in a Python environment with those packages
    (processors/fmuenv.py), for a Python FMU importing packages the server lacks."""

    name: str
    fmu: str
    isolated: bool = False
    python_requirements: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Connection:
    """An output of one instance feeding an input of another (or of the same) instance."""

    source: Port
    target: Port


ConstraintKind = Literal["zerocrossing", "boundeddifference", "samplingrate", "fmumaxstepsize"]


@dataclass(frozen=True, slots=True)
class Constraint:
    """One of Maestro's var-step constraints (constraints.py applies them), as its file
    writes it: `name` is its key in `constraints`. zerocrossing: `ports` (one, or two whose
    difference crosses zero), `order` of the prediction (1 or 2), `abstol`, `safety`;
    boundeddifference: `ports`, `abstol`, `reltol`, `safety`, `skip_discrete`; samplingrate:
    samples at (`start_time` + k `rate`) 10^`base` s; fmumaxstepsize: nothing. None: the
    default constraints.py gives."""

    name: str
    kind: ConstraintKind
    ports: tuple[Port, ...] = ()
    order: int = 1
    abstol: float | None = None
    reltol: float | None = None
    safety: float | None = None
    skip_discrete: bool = True
    base: int = 0
    rate: int = 1
    start_time: int = 0


@dataclass(frozen=True, slots=True)
class Algorithm:
    """How the master steps: a fixed step of `size`, or a variable one starting at `size`
    and kept between `min_size` and `max_size`; Jacobi (every instance steps from the same
    inputs) or Gauss-Seidel (an instance sees the outputs of those stepped before it).
    Var-step only: `tolerance`, its relative tolerance (None: varstep.TOLERANCE), and
    Maestro's `constraints` on its steps."""

    kind: Literal["fixed-step", "var-step"]
    size: float
    min_size: float | None = None
    max_size: float | None = None
    master: Literal["jacobi", "gauss-seidel"] = "gauss-seidel"
    tolerance: float | None = None
    constraints: tuple[Constraint, ...] = ()


@dataclass(frozen=True, slots=True)
class System:
    """A whole co-simulation as read from a file. `parameters` are start values and
    parameters by port; `log_variables` the variables recorded per instance name; `source`
    the format it was read from ("maestro", "ssp" or "yaml")."""

    instances: tuple[Instance, ...]
    connections: tuple[Connection, ...]
    parameters: Mapping[Port, float | int | bool | str]
    log_variables: Mapping[str, tuple[str, ...]]
    algorithm: Algorithm
    start_time: float = 0.0
    end_time: float | None = None
    source: str = ""


class CosimFormatError(InvalidInputError):
    """A co-simulation file that cannot be read; the message names the file, the key or
    element, and what is wrong with it."""
