"""A batch co-simulation run: from a System and its FMU files to the recorded rows.

Every FMU is instantiated (FMI 2 or FMI 3 co-simulation), given its parameters and start
values, initialized with the connections exchanged once, stepped from start to end by the
master (a loop over a Session, session.py), then terminated and freed, whatever happened: a
failed run leaves no instance, no loaded library and no extracted folder behind.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from twinlink.domain.errors import InvalidInputError

from .master import Progress
from .model import System
from .results import Result
from .session import Session
from .slaves import CosimRunError

__all__ = ["CosimRunError", "Result", "run"]


def run(
    system: System,
    fmu_paths: Mapping[str, Path],
    *,
    progress: Progress | None = None,
    stop: threading.Event | None = None,
) -> Result:
    """Run `system` as fast as possible and return its recorded rows.

    `fmu_paths` maps each instance's `fmu` (as the file names it) to the FMU file. `progress`
    is called with the fraction done (at most about 100 times, and 1.0 at the end); `stop`,
    once set, ends the run after the current step with the rows so far. Raises
    InvalidInputError for a system this master cannot run, CosimRunError (naming the
    instance) when an FMU fails.
    """
    start, end = system.start_time, system.end_time
    if end is None or not end > start:
        raise InvalidInputError(f"a batch run needs an end time after the start time ({start:g})")
    ended = ""
    with Session(system, fmu_paths) as session:
        rows = [session.initialize()]
        span, mark = end - start, 0.01
        while True:
            if stop is not None and stop.is_set():
                ended = f"stopped at t = {session.time:g} s"
                break
            row = session.step()
            if row is None:
                break
            rows.append(row)
            if progress is not None and (done := (session.time - start) / span) >= mark:
                progress(done)
                mark = done + 0.01
        ended = ended or session.ended
    if progress is not None and not ended:
        progress(1.0)
    return Result(session.columns, np.vstack(rows), ended)
