"""Co-simulations made through the API (cosim/service.py): a system read from an uploaded file,
its FMUs resolved into a folder of its own, and the state of its latest run.

A co-simulation is `created`, `running` while its process runs, then `finished`, `stopped`
or `failed`; starting an ended one runs it again (new results). A record found `running` by
a server that starts was cut off by a stop or a crash: it is marked `failed` then.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

CosimState = Literal["created", "running", "finished", "stopped", "failed"]
STATES: tuple[str, ...] = ("created", "running", "finished", "stopped", "failed")
ENDED: frozenset[str] = frozenset({"finished", "stopped", "failed"})
MODES: tuple[str, ...] = ("batch", "realtime")


@dataclass(slots=True)
class CosimRecord:
    id: int
    name: str
    owner_id: int | None  # who created it
    twin: str | None  # the twin whose history gets the results (its slug), or None
    prefix: str  # of the signals written into the twin's history
    stream: str  # the twin's stream they go to
    mode: str  # batch | realtime
    factor: float  # realtime: 1.0 = wall clock, 2.0 = twice as fast
    state: str
    format: str  # maestro | ssp | yaml: how `document` is read
    document: str  # the system's file, relative to the co-simulation's folder
    # Each FMU reference the system makes ("mass.fmu", "lib:...") -> its file, relative to the
    # folder, and where it came from ("upload", "twin", the pinned library ref).
    fmus: dict[str, dict[str, str]] = field(default_factory=dict)
    system: dict[str, Any] = field(default_factory=dict)  # the view of the System, made once
    columns: list[str] = field(default_factory=list)  # of the latest run's results
    rows: int = 0
    progress: float = 0.0  # 0..1
    sim_time: float | None = None
    message: str = ""  # why it failed or ended early
    created_ns: int = 0
    started_ns: int | None = None
    ended_ns: int | None = None
    node: str | None = None  # the node that runs (ran) it

    @property
    def ended(self) -> bool:
        return self.state in ENDED
