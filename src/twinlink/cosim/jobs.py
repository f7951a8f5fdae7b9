"""A co-simulation run in a process of its own, seen from the server (asyncio).

The run is `python -m twinlink.cosim.worker` (worker.py): it is given its job as one JSON
document on stdin and answers with JSON lines on stdout (the columns, progress, batches of
rows, and how it ended). A native FMU that crashes takes down only that process: the run
ends "failed" with the exit status and the last lines the process wrote on stderr (where
Python's faulthandler writes the stack it crashed in), and the server goes on.

The process runs in a session of its own, with an environment built from nothing (the
server's settings and secrets never reach FMU code). A stop is SIGTERM to the worker,
which ends after the step it is in, keeping its rows; one that does not end within the
grace period is killed with everything it started (its process group).
"""

from __future__ import annotations

import asyncio
import contextlib
import inspect
import logging
import math
import os
import signal
import sys
from collections import deque
from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import orjson

from twinlink.processors.fmuenv import pip_environment

from .kinds import ENVS_DIR_VAR

log = logging.getLogger("twinlink.cosim")

STOP_GRACE_S = 5.0  # a stopped run's time to end its step and close its FMUs
STDERR_LINES = 30  # the last lines of the worker's stderr kept for a crash's message
_LINE_LIMIT = 2**26  # a batch of 1000 rows of many columns is one line
# What the worker's environment takes from the server's: nothing that configures twinlink
# (TWINLINK_*: the secret key, the store's URL), only what Python and FMUs need to run.
_PASSED_ENV = ("PATH", "LANG", "LC_ALL", "TMPDIR", "PYTHONPATH", "LD_LIBRARY_PATH")

Mode = Literal["batch", "realtime"]
Format = Literal["maestro", "ssp", "yaml"]
End = Literal["finished", "stopped", "failed"]
Rows = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class JobSpec:
    """One run, as the worker is given it: the document read as `format`, each instance's
    FMU reference (Instance.fmu) to its file, the mode and real-time factor, where the CSV
    goes, and whether rows are sent back (`stream`) in batches of `batch_ms` of wall time
    (or 1000 rows)."""

    document: Path
    format: Format
    fmu_paths: Mapping[str, Path]
    csv: Path
    mode: Mode = "batch"
    factor: float = 1.0
    stream: bool = True
    batch_ms: int = 50
    envs_dir: Path | None = None  # where Python FMUs' environments are built (fmu-envs)

    def to_json(self) -> bytes:
        return orjson.dumps(
            {
                "document": str(self.document),
                "format": self.format,
                "fmu_paths": {ref: str(path) for ref, path in self.fmu_paths.items()},
                "mode": self.mode,
                "factor": self.factor,
                "csv": str(self.csv),
                "stream": self.stream,
                "batch_ms": self.batch_ms,
            }
        )

    @classmethod
    def from_json(cls, data: bytes | str) -> JobSpec:
        raw = orjson.loads(data)
        if raw.get("format") not in ("maestro", "ssp", "yaml"):
            raise ValueError(f"format must be maestro, ssp or yaml, not {raw.get('format')!r}")
        if raw.get("mode", "batch") not in ("batch", "realtime"):
            raise ValueError(f"mode must be batch or realtime, not {raw.get('mode')!r}")
        factor = float(raw.get("factor", 1.0))
        if not (math.isfinite(factor) and factor > 0):
            raise ValueError(f"the real-time factor must be a positive number, not {factor:g}")
        return cls(
            document=Path(raw["document"]),
            format=raw["format"],
            fmu_paths={str(ref): Path(path) for ref, path in raw["fmu_paths"].items()},
            csv=Path(raw["csv"]),
            mode=raw.get("mode", "batch"),
            factor=factor,
            stream=bool(raw.get("stream", True)),
            batch_ms=int(raw.get("batch_ms", 50)),
        )


# Each callback may be a plain function or a coroutine function (awaited before the next
# line is read: a slow consumer slows the run down instead of piling rows up in memory).
OnColumns = Callable[[list[str]], Awaitable[None] | None]
OnProgress = Callable[[float, float], Awaitable[None] | None]  # fraction done, sim time
OnRows = Callable[[Rows], Awaitable[None] | None]  # rows x columns, "time" first


async def _call(callback: Callable[..., Awaitable[None] | None], *args: Any) -> None:
    result = callback(*args)
    if inspect.isawaitable(result):
        await result


@dataclass(slots=True)
class _Ended:
    end: End | None = None
    message: str = ""
    stopping: bool = False  # stop() was called
    killed: bool = False  # ...and the worker had to be killed
    time: float | None = None  # the last simulated time reported (progress, rows)
    in_process: list[str] | None = None  # the instances the worker runs itself, as it said
    stderr: deque[str] = field(default_factory=lambda: deque(maxlen=STDERR_LINES))


def worker_environment(home: Path, envs_dir: Path | None = None) -> dict[str, str]:
    """The worker's environment: built from nothing, with what Python and FMUs need, and
    with `envs_dir`, what pip needs to build a Python FMU's environment there (the index,
    proxy and certificate settings, as the FMU processors' builds get: fmuenv.py)."""
    env = {"HOME": str(home), "LANG": "C.UTF-8"}
    env.update({k: os.environ[k] for k in _PASSED_ENV if k in os.environ})
    if envs_dir is not None:
        env.update(pip_environment())
        env["HOME"] = str(home)  # pip's cache and config: the run's, not the server's
        env[ENVS_DIR_VAR] = str(envs_dir)
    return env


class CosimJob:
    """One co-simulation run in a worker process.

        job = CosimJob(spec, on_columns=..., on_progress=..., on_rows=...)
        await job.start()
        end, message = await job.wait()   # ("finished" | "stopped" | "failed", why)

    `await job.stop()` (from another task) asks the run to end; `wait` then returns
    "stopped". `wait` must be awaited for every started job: it reads the worker's output,
    calls the callbacks, and reaps the process; cancelling it stops the run."""

    def __init__(
        self,
        spec: JobSpec,
        *,
        on_columns: OnColumns,
        on_progress: OnProgress,
        on_rows: OnRows,
        python: str = sys.executable,
        grace_s: float = STOP_GRACE_S,
    ) -> None:
        self.spec = spec
        self.on_columns = on_columns
        self.on_progress = on_progress
        self.on_rows = on_rows
        self.python = python
        self.grace_s = grace_s
        self.pid: int | None = None
        self._proc: asyncio.subprocess.Process | None = None
        self._state = _Ended()

    @property
    def stderr_tail(self) -> list[str]:
        """The last lines the worker wrote on stderr (an FMU's log, a crash's stack)."""
        return list(self._state.stderr)

    async def start(self) -> None:
        """Start the worker and give it its job. A worker that cannot start is a run that
        ended "failed" (wait says why), never an exception."""
        home = self.spec.csv.parent
        env = worker_environment(home, self.spec.envs_dir)
        try:
            self._proc = await asyncio.create_subprocess_exec(
                self.python, "-m", "twinlink.cosim.worker",
                stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE,
                stderr=asyncio.subprocess.PIPE, cwd=home, env=env,
                start_new_session=True, limit=_LINE_LIMIT,
            )  # fmt: skip
        except OSError as err:
            self._state.end, self._state.message = "failed", f"could not start: {err}"
            return
        self.pid = self._proc.pid
        assert self._proc.stdin is not None
        self._proc.stdin.write(self.spec.to_json())
        with contextlib.suppress(ConnectionError):
            await self._proc.stdin.drain()
        self._proc.stdin.close()

    async def wait(self) -> tuple[End, str]:
        """Until the run ends: how ("finished", "stopped" or "failed") and why (an FMU's
        termination, where it stopped, what failed)."""
        proc = self._proc
        if proc is None:
            return self._state.end or "failed", self._state.message or "it was never started"
        assert proc.stdout is not None and proc.stderr is not None
        try:
            await asyncio.gather(self._read(proc.stdout), self._read_stderr(proc.stderr))
            await proc.wait()
        except BaseException:
            await asyncio.shield(self.stop())
            raise
        finally:
            _kill_group(proc.pid)  # whatever it started that outlived it
        return self._ended(proc.returncode)

    async def stop(self) -> None:
        """Ask the run to end after its current step (SIGTERM to the worker alone: its
        isolated FMUs' processes are its to close), then kill its process group if it has
        not ended within the grace period. Returns once the worker has exited."""
        proc = self._proc
        self._state.stopping = True
        if proc is None or proc.returncode is not None:
            return
        with contextlib.suppress(ProcessLookupError):
            proc.send_signal(signal.SIGTERM)
        try:
            await asyncio.wait_for(proc.wait(), self.grace_s)
        except TimeoutError:
            self._state.killed = True
            _kill_group(proc.pid)
            await proc.wait()

    async def _read(self, stdout: asyncio.StreamReader) -> None:
        while line := await stdout.readline():
            try:
                message = orjson.loads(line)
            except orjson.JSONDecodeError:  # not ours: something native wrote on stdout
                self._state.stderr.append(line.decode("utf-8", "replace").rstrip()[:500])
                continue
            await self._took(message)

    async def _took(self, message: dict[str, Any]) -> None:
        if "rows" in message:
            rows = np.array(message["rows"], dtype=np.float64)
            if len(rows):
                self._state.time = float(rows[-1, 0])
            await _call(self.on_rows, rows)
        elif "progress" in message:
            self._state.time = float(message["time"])
            await _call(self.on_progress, float(message["progress"]), self._state.time)
        elif "columns" in message:
            await _call(self.on_columns, list(message["columns"]))
        elif "in_process" in message:
            self._state.in_process = [str(label) for label in message["in_process"]]
        elif "end" in message:
            self._state.end, self._state.message = message["end"], str(message["message"])

    async def _read_stderr(self, stderr: asyncio.StreamReader) -> None:
        while line := await stderr.readline():
            text = line.decode("utf-8", "replace").rstrip()
            if text:
                self._state.stderr.append(text[:500])
                log.debug("cosim worker %s: %s", self.pid, text)

    def _ended(self, code: int | None) -> tuple[End, str]:
        state = self._state
        if state.end is not None:
            return state.end, state.message
        if state.stopping:
            at = f" at t = {state.time:g} s" if state.time is not None else ""
            how = (
                f"killed after {self.grace_s:g} s: it did not end its step"
                if state.killed
                else "stopped"
            )
            return "stopped", f"{how}{at}"
        return "failed", _crash_message(code, state)


def _crash_message(code: int | None, state: _Ended) -> str:
    if code is not None and code < 0:
        try:
            name = signal.Signals(-code).name
            how = f"killed by signal {name} ({signal.strsignal(-code) or name})"
        except ValueError:
            how = f"killed by signal {-code}"
    else:
        how = f"exited with status {code} without saying how the run ended"
    at = f" at t = {state.time:g} s" if state.time is not None else ""
    message = f"the co-simulation process crashed{at} ({how}){_culprits(state.in_process)}"
    tail = "\n".join(state.stderr)
    return f"{message}; its last output:\n{tail}" if tail else message


def _culprits(in_process: list[str] | None) -> str:
    """Whose native code most likely crashed the worker: the FMUs it ran itself (an
    isolated one's crash is reported by the worker, by name)."""
    if not in_process:
        return ""
    if len(in_process) == 1:
        return f", in the native code of {in_process[0]}"
    return (
        f", in the native code of one of the FMUs it runs itself ({', '.join(in_process)}); "
        "run them with isolated: true to learn which (each in a process of its own, whose "
        "crash names its instance)"
    )


def _kill_group(pgid: int) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pgid, signal.SIGKILL)
