"""A co-simulation run in a process of its own: `python -m twinlink.cosim.worker`.

It reads one job (jobs.JobSpec, JSON) on stdin, runs the co-simulation in a Session (batch:
as fast as it goes; realtime: paced to the wall clock, pacing.py), writes the CSV as it
goes, and answers with JSON lines on stdout:

    {"in_process": ["instance 'm1' (msd1.fmu)", ...]}   the FMUs this process runs itself
    {"columns": ["time", "{msd1}.m1.x1", ...]}
    {"progress": 0.42, "time": 4.2}      about 100 a run (real time: 1/s too), and at the end
    {"rows": [[t, v1, ...], ...]}        with "stream": every batch_ms or 1000 rows
    {"end": "finished" | "stopped" | "failed", "message": "..."}

SIGTERM stops the run after the step it is in (its rows so far kept: "stopped"). Rows are
buffered for at most batch_ms of wall time, then written to the CSV (flushed) and sent,
so a run that fails, or a process killed outright, leaves the CSV up to its last batch.
A native crash (a segfault in an FMU) cannot be reported from here: faulthandler writes
the Python stack on stderr, and the server (jobs.py) tells it from the exit status.
"""

from __future__ import annotations

import csv
import faulthandler
import logging
import os
import resource
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from types import FrameType
from typing import IO, Any

import numpy as np
import orjson

from twinlink.domain.errors import TwinlinkError

from .jobs import End, JobSpec
from .kinds import is_python_fmu
from .maestro import read_maestro
from .model import System
from .pacing import run_paced
from .recording import every_output
from .session import Row, Session
from .ssp import read_ssp
from .yamlform import read_yaml

log = logging.getLogger("twinlink.cosim.worker")

MAX_BATCH_ROWS = 1000
PROGRESS_EVERY = 0.01  # of the span: at most about 100 progress lines a run
PROGRESS_WALL_NS = 1_000_000_000  # in real time, also at least once a second


class Output:
    """JSON lines on stdout, each flushed as written. A reader that went away (the server
    died) stops the run at the next line: nobody is left to tell. A real-time run writes
    a line at least once a second, a batch run once per 1 % of it and at its end."""

    def __init__(self, stream: IO[bytes], stop: threading.Event) -> None:
        self.stream = stream
        self.stop = stop
        self.closed = False

    def send(self, message: dict[str, Any]) -> None:
        if self.closed:
            return
        try:
            self.stream.write(orjson.dumps(message, option=orjson.OPT_SERIALIZE_NUMPY) + b"\n")
            self.stream.flush()
        except (BrokenPipeError, ValueError):
            self.closed = True
            self.stop.set()


class Rows:
    """Rows gathered into a block, then written to the CSV and sent as one batch: at most
    `batch_ns` of wall time or MAX_BATCH_ROWS after the first of them. Progress is told at
    a batch when it moved by PROGRESS_EVERY of the span, and in real time also when a
    second has passed (a long or open-ended run's simulated time shows as it goes)."""

    def __init__(
        self,
        spec: JobSpec,
        session: Session,
        out: Output,
        csv_file: IO[str],
        clock: Callable[[], int] = time.perf_counter_ns,
    ) -> None:
        system = session.system
        self.out = out
        self.stream = spec.stream
        self.batch_ns = max(1, spec.batch_ms) * 1_000_000
        self.clock = clock
        self.file = csv_file
        csv.writer(csv_file, lineterminator="\n").writerow(session.columns)  # as Result does
        self.file.flush()  # a run that dies at its first step still says what it recorded
        self.block = np.empty((MAX_BATCH_ROWS, len(session.columns)))
        self.count = 0
        self.first_ns = 0
        self.start = system.start_time
        end = system.end_time
        self.span = end - system.start_time if end is not None else None
        self.told = -1.0  # the progress last told...
        self.told_ns = 0  # ...and when
        self.every_ns = PROGRESS_WALL_NS if spec.mode == "realtime" else None
        self.time = system.start_time

    def add(self, row: Row) -> None:
        if self.count == 0:
            self.first_ns = self.clock()
        self.block[self.count] = row
        self.count += 1
        if self.count == MAX_BATCH_ROWS or self.clock() - self.first_ns >= self.batch_ns:
            self.flush()

    def flush(self, *, last: bool = False) -> None:
        if self.count:
            rows = self.block[: self.count]
            self.time = float(rows[-1, 0])
            # As results.Result writes them (csv.writer with each value's repr), a quarter
            # faster: a float's repr holds no comma, quote or newline for csv to quote.
            self.file.write("".join(",".join(map(repr, row)) + "\n" for row in rows.tolist()))
            self.file.flush()
            if self.stream:
                self.out.send({"rows": rows})
            self.count = 0
        done = (self.time - self.start) / self.span if self.span else 0.0
        now = self.clock()
        if (
            last
            or done >= self.told + PROGRESS_EVERY
            or (self.every_ns is not None and now - self.told_ns >= self.every_ns)
        ):
            self.out.send({"progress": done, "time": self.time})
            self.told, self.told_ns = done, now


def read_system(spec: JobSpec) -> System:
    if spec.format == "ssp":
        return read_ssp(spec.document)
    if spec.format == "yaml":
        return read_yaml(spec.document)
    return read_maestro(spec.document)


def in_process(system: System, spec: JobSpec) -> list[str]:
    """The instances whose FMU runs in this process (not isolated, not a Python FMU), as
    their labels: told before any is opened, so that a crash of this process can be put
    down to them (to one, when it is the only one)."""
    return [
        f"instance {i.name!r} ({Path(i.fmu).name})"
        for i in system.instances
        if not (i.isolated or is_python_fmu(spec.fmu_paths.get(i.fmu, Path(i.fmu))))
    ]


def run(spec: JobSpec, stop: threading.Event, out: Output) -> tuple[End, str]:
    """Run the job; how it ended and why. Raises what the Session raises (TwinlinkError
    for a system that cannot run or an FMU that failed)."""
    system = every_output(read_system(spec), spec.fmu_paths)
    if spec.mode == "batch" and system.end_time is None:
        return "failed", "a batch run needs an end time: give the document one"
    out.send({"in_process": in_process(system, spec)})
    with Session(system, spec.fmu_paths) as session:
        out.send({"columns": list(session.columns)})
        with spec.csv.open("w", newline="", encoding="utf-8") as csv_file:
            rows = Rows(spec, session, out, csv_file)
            try:
                rows.add(session.initialize())
                finished = _step(session, spec, stop, rows.add)
            finally:
                rows.flush(last=True)  # what was computed is kept, whatever happened
    # What the run did not do as the file asked (a var-step constraint, a step kept over
    # its tolerance), once each, after how it ended.
    notes = "".join(f"; {note}" for note in dict.fromkeys(session.warnings))
    if not finished:
        return "stopped", f"stopped at t = {session.time:g} s{notes}"
    return "finished", f"{session.ended or finished}{notes}"


def _step(
    session: Session, spec: JobSpec, stop: threading.Event, on_row: Callable[[Row], None]
) -> str:
    """Step to the end; "" when stopped first, else what to say of the finished run."""
    began = time.monotonic()
    if spec.mode == "realtime":
        jitter = run_paced(session, spec.factor, stop, on_row)
        said = f"real time x{spec.factor:g}: {jitter}"
    else:
        while not stop.is_set() and (row := session.step()) is not None:
            on_row(row)
        said = f"{session.steps} steps in {time.monotonic() - began:.3g} s"
    return "" if stop.is_set() and not _at_end(session) else said


def _at_end(session: Session) -> bool:
    """The session has nothing left to step (a stop that came with the last step is not a
    stop)."""
    end = session.system.end_time
    return bool(session.ended) or (end is not None and session.time >= end)


def _own_stdout() -> IO[bytes]:
    """The protocol's own copy of stdout; file descriptor 1 then goes to stderr, so what an
    FMU's native code prints (printf) or Python code prints never lands inside a line."""
    sys.stdout.flush()
    protocol = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    return protocol


def main() -> int:
    # A stop is the server's SIGTERM (after the current step); Ctrl-C is the server's own.
    stop = threading.Event()

    def stopping(_signum: int, _frame: FrameType | None) -> None:
        stop.set()

    signal.signal(signal.SIGTERM, stopping)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # a crashing FMU leaves no core file
    faulthandler.enable(sys.stderr)  # ...but its stack, for the run's message
    logging.basicConfig(
        stream=sys.stderr, level=logging.INFO, format="%(levelname)s %(name)s: %(message)s"
    )
    out = Output(_own_stdout(), stop)
    try:
        spec = JobSpec.from_json(sys.stdin.buffer.read())
    except (ValueError, KeyError, TypeError) as err:  # orjson's errors are ValueErrors
        why = f"it has no {err.args[0]!r}" if isinstance(err, KeyError) else str(err)
        out.send({"end": "failed", "message": f"the job cannot be read: {why}"})
        return 0
    try:
        end, message = run(spec, stop, out)
    except TwinlinkError as err:  # InvalidInputError, CosimFormatError, CosimRunError
        end, message = "failed", str(err)
    except Exception as err:
        traceback.print_exc()
        end, message = "failed", f"{type(err).__name__}: {err}"
    out.send({"end": end, "message": message})
    return 0


if __name__ == "__main__":
    sys.exit(main())
