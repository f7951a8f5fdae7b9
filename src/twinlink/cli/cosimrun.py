"""`twinlink cosim run` and `check` on this machine: a co-simulation file read into a System
with its FMU files found, run by a Session (as fast as possible, or paced to the wall clock),
each row written as CSV and, when asked, sent as a device's samples (cosimsend.py).

A file's FMUs are files beside it (Maestro JSON, YAML) or inside it (an SSP archive, unpacked
into a temporary folder removed at the end). A `lib:` reference names the server's library:
the local run says so and points to `twinlink cosim create`, which resolves it there.
"""

from __future__ import annotations

import csv
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import IO

import click
import numpy as np
import numpy.typing as npt

from twinlink.cli.cosimsend import DeviceSender, SendError
from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import CosimFormatError, System
from twinlink.cosim.pacing import run_paced
from twinlink.cosim.reading import format_of, read_system
from twinlink.cosim.recording import every_output
from twinlink.cosim.session import Session
from twinlink.cosim.ssp import extract
from twinlink.domain.errors import InvalidInputError

Row = npt.NDArray[np.float64]
Say = Callable[[str], None]
PROGRESS_MARKS = 10  # progress lines per run (each 10 %), so a run's log stays short
FLUSH_S = 0.5  # a paced run's CSV is flushed this often


@dataclass(frozen=True, slots=True)
class Loaded:
    """A file read: its System and each instance's FMU file (by the name the file gives)."""

    path: Path
    system: System
    fmu_paths: dict[str, Path]
    every_output: bool = False  # the file named nothing to record: every output is


@contextmanager
def load(
    path: Path,
    *,
    settings: Path | None = None,
    end: float | None = None,
    step: float | None = None,
) -> Iterator[Loaded]:
    """Read the co-simulation at `path` (cosim.reading: a Maestro multi-model or its coe.json,
    twinlink's YAML form, an SSP archive), with `end` and `step` replacing the file's end
    time and step size. CosimFormatError names the file and what is wrong; an SSP's
    unpacked FMUs are removed when the block ends."""
    if not path.is_file():
        raise CosimFormatError(f"{path}: no such file")
    unpacked: Path | None = None
    try:
        if settings is not None:
            if format_of(path) != "maestro":
                raise CosimFormatError(f"{path}: --settings goes with a Maestro multi-model")
            system = read_maestro(path, settings=settings)
        else:
            system = read_system(path, step_size=step)
        base = path.parent
        if system.source == "ssp":
            unpacked = Path(tempfile.mkdtemp(prefix="twinlink-ssp-"))
            extract(path, unpacked)
            base = unpacked
        system = _override(system, end, step)
        fmu_paths = _fmu_paths(path, system, base)
        recorded = every_output(system, fmu_paths)
        yield Loaded(path, recorded, fmu_paths, every_output=recorded is not system)
    finally:
        if unpacked is not None:
            shutil.rmtree(unpacked, ignore_errors=True)


def _override(system: System, end: float | None, step: float | None) -> System:
    if step is not None:
        if not step > 0:
            raise click.BadParameter(f"must be positive, not {step:g}", param_hint="--step")
        system = replace(system, algorithm=replace(system.algorithm, size=step))
    if end is not None:
        system = replace(system, end_time=end)
    return system


def _fmu_paths(path: Path, system: System, base: Path) -> dict[str, Path]:
    found: dict[str, Path] = {}
    for instance in system.instances:
        if instance.fmu.startswith("lib:"):
            raise CosimFormatError(
                f"{path}: instance {instance.name!r}: its FMU {instance.fmu} is in the "
                "server's library; pull it (`twinlink lib pull`) and name the file, or run it "
                "on the server with `twinlink cosim create`"
            )
        fmu = base / instance.fmu
        if not fmu.is_file():
            raise CosimFormatError(
                f"{path}: instance {instance.name!r}: its FMU {instance.fmu} is not there "
                f"({fmu} does not exist)"
            )
        found[instance.fmu] = fmu
    return found


def signal_name(column: str, prefix: str = "") -> str:
    """A column as a signal of the twin's history: "instance.variable" with Maestro's braces
    taken off its FMU key (`{msd1}.msd1i.x1` is `msd1.msd1i.x1`), after `prefix`."""
    if column.startswith("{") and "}." in column:
        key, rest = column[1:].split("}.", 1)
        column = f"{key}.{rest}"
    return prefix + column


class Rows:
    """Where each row goes: the CSV (Maestro's outputs.csv: a header, then each value in
    its shortest exact form) and the device sender, with progress said now and then."""

    def __init__(
        self,
        columns: tuple[str, ...],
        out: IO[str],
        sender: DeviceSender | None,
        system: System,
        say: Say,
        *,
        live: bool = False,
    ) -> None:
        self._writer = csv.writer(out, lineterminator="\n")
        self._writer.writerow(columns)
        self._out = out
        self._sender = sender
        self._start = system.start_time
        self._span = None if system.end_time is None else system.end_time - system.start_time
        self._say = say
        self._mark = 1
        self._live = live
        self._flushed = time.monotonic()
        self.count = 0
        self.last_time = system.start_time

    def __call__(self, row: Row) -> None:
        values = row.tolist()
        self._writer.writerow([repr(v) for v in values])
        if self._sender is not None:
            self._sender.add(row)
        self.count += 1
        self.last_time = values[0]
        if self._live and time.monotonic() - self._flushed >= FLUSH_S:
            self._out.flush()  # a paced run's CSV grows as it runs (tail -f follows it)
            self._flushed = time.monotonic()
        if self._span:
            done = (values[0] - self._start) / self._span
            if done * PROGRESS_MARKS >= self._mark and self._mark < PROGRESS_MARKS:
                self._say(f"{done:4.0%}  t = {values[0]:g} s")
                self._mark = int(done * PROGRESS_MARKS) + 1

    def flush(self) -> None:
        self._out.flush()


@dataclass(frozen=True, slots=True)
class Outcome:
    rows: int
    last_time: float
    ended: str  # "" when the run reached its end time
    seconds: float  # wall-clock time of the run
    jitter: str = ""  # real time: how late the steps were (p50, p99, max in ms)


def execute(
    loaded: Loaded,
    out: IO[str],
    *,
    sender: Callable[[tuple[str, ...]], DeviceSender | None],
    realtime: float | None,
    stop: threading.Event,
    say: Say,
) -> Outcome:
    """Run the co-simulation: the rows to `out` as CSV and to the sender `sender(columns)`
    makes (if any), progress to `say`. As fast as possible, or paced at `realtime` times
    the wall clock; either ends early once `stop` is set. Raises InvalidInputError for a
    system that cannot run, CosimRunError naming the instance whose FMU failed, SendError."""
    system = loaded.system
    if system.end_time is None and realtime is None:
        raise InvalidInputError(
            f"{loaded.path}: has no end time: give one with --end (or run it in real time "
            "with --realtime until it is stopped)"
        )
    began = time.perf_counter()
    with Session(system, loaded.fmu_paths) as session:
        device = sender(session.columns)
        try:
            rows = Rows(session.columns, out, device, system, say, live=realtime is not None)
            jitter = ""
            if realtime is None:
                ended = _batch(session, rows, stop)
            else:
                ended, jitter = _paced(session, rows, stop, realtime)
            rows.flush()
        except BaseException:
            if device is not None:
                device.abandon()
            raise
        if device is not None:
            sent = device.close()
            batches = f"{sent.batches} batch" + ("" if sent.batches == 1 else "es")
            say(f"sent {sent.accepted} samples in {batches}")
            if sent.rejected:
                raise SendError(
                    f"{sent.rejected} samples were refused by the twin: {sent.first_rejection}"
                )
    return Outcome(rows.count, rows.last_time, ended, time.perf_counter() - began, jitter)


def _batch(session: Session, rows: Rows, stop: threading.Event) -> str:
    """Step to the end time, or until `stop` is set; why the run ended early ("" if not)."""
    rows(session.initialize())
    while not stop.is_set():
        row = session.step()
        if row is None:
            return session.ended
        rows(row)
    return f"stopped at t = {session.time:g} s"


def _paced(session: Session, rows: Rows, stop: threading.Event, factor: float) -> tuple[str, str]:
    rows(session.initialize())
    jitter = run_paced(session, factor, stop, rows)
    ended = session.ended or (f"stopped at t = {session.time:g} s" if stop.is_set() else "")
    return ended, f"p50 {jitter.p50:.3f} ms, p99 {jitter.p99:.3f} ms, max {jitter.max:.3f} ms"
