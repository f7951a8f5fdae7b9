"""An instance in a process of its own: a Python FMU (pythonfmu), or one the file asks to
isolate (`isolated: true`).

The child (`python -m twinlink.cosim.slaveproc`) runs the instance as a Slave or MeSlave;
this side keeps the same Groups and numpy buffers a Slave has, so the master does not see the
difference. Each read, write and step is one round trip on the child's pipes, the values as
the buffers' raw bytes. A child that dies (a segfault, os._exit, a kill) fails the run with a
CosimRunError naming the instance and how its process ended; `close` never hangs: the child
is asked to close, then killed.
"""

from __future__ import annotations

import contextlib
import logging
import select
import signal
import subprocess
import sys
from pathlib import Path
from typing import IO, Any, NoReturn

import numpy as np
import orjson

from twinlink.processors.blueprints._fmu_fmi import Fmi2Api, Fmi3Api
from twinlink.processors.fmuinfo import FmuError, FmuVariable, Scalar, inspect_fmu
from twinlink.processors.workerenv import worker_environment

from . import frames as p
from .slaves import CosimRunError, FmuTerminated, Group

_log = logging.getLogger("twinlink.cosim")
CLOSE_TIMEOUT_S = 10.0  # for the child to terminate and free its FMU before it is killed
KILL_TIMEOUT_S = 5.0
STDERR_TAIL = 2000  # characters of the child's stderr in a message


def ended(returncode: int) -> str:
    """How a process ended, for a person: "killed by SIGSEGV", "exit status 3"."""
    if returncode < 0:
        with contextlib.suppress(ValueError):
            return f"killed by {signal.Signals(-returncode).name}"
        return f"killed by signal {-returncode}"
    return f"exit status {returncode}"


class IsolatedSlave:
    """A Slave in a child process; a SlaveLike to the master."""

    def __init__(
        self, name: str, fmu_path: Path, workdir: Path, *, python: str | None = None
    ) -> None:
        self.name = name
        self.label = f"instance {name!r} ({fmu_path.name})"
        try:
            self.info = inspect_fmu(fmu_path)
        except FmuError as err:
            raise CosimRunError(f"{self.label}: {err}") from err
        self.can_rollback = False
        self._dtypes = (Fmi3Api if self.info.fmi_version.startswith("3") else Fmi2Api).DTYPES
        self._outputs: dict[str, Group] = {}
        self._inputs: dict[str, Group] = {}
        self._ports: list[tuple[str, bool]] = []
        workdir.mkdir(parents=True, exist_ok=True)
        self._stderr_path = workdir / "stderr.txt"
        command = [python or sys.executable, "-m", "twinlink.cosim.slaveproc"]
        try:
            with self._stderr_path.open("wb") as stderr:
                self.proc = subprocess.Popen(
                    command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=stderr,
                    env=worker_environment(), cwd=workdir,
                )  # fmt: skip
        except OSError as err:
            raise CosimRunError(f"{self.label}: cannot start its process: {err}") from err
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self._requests: IO[bytes] = self.proc.stdin
        self._answers: IO[bytes] = self.proc.stdout
        self.pid = self.proc.pid
        try:
            spec = {"name": name, "fmu": str(fmu_path.resolve()), "workdir": str(workdir / "fmu")}
            opened = orjson.loads(self._call(p.OPEN, orjson.dumps(spec)))
        except BaseException:
            self.close()
            raise
        self.can_rollback = bool(opened["can_rollback"])

    # the protocol ----------------------------------------------------------------------------

    def _call(self, op: int, payload: bytes = b"") -> bytes:
        """One round trip; the child's errors raised here as they were raised there."""
        try:
            self._requests.write(p.HEADER.pack(op, len(payload)) + payload)
            self._requests.flush()
            status, size = p.HEADER.unpack(p.read_exactly(self._answers, p.HEADER.size))
            answer = p.read_exactly(self._answers, size)
        except (EOFError, OSError, ValueError):  # a broken pipe, a closed file: it died
            self._died()
        if status == p.OK:
            return answer
        if status == p.TERMINATED:
            message, time = orjson.loads(answer)
            raise FmuTerminated(message, time)
        text = answer.decode("utf-8", "replace")
        if status == p.RUN_ERROR:
            raise CosimRunError(text)
        raise CosimRunError(f"{self.label}: its process failed: {text}")

    def _died(self) -> NoReturn:
        try:
            code = self.proc.wait(KILL_TIMEOUT_S)
        except subprocess.TimeoutExpired:  # its pipes closed but it lives on: end it
            self.proc.kill()
            code = self.proc.wait()
        tail = self._stderr_tail()
        raise CosimRunError(
            f"{self.label}: its process (pid {self.pid}) ended unexpectedly, {ended(code)}"
            + (f"; it wrote: {tail}" if tail else "")
        )

    def _stderr_tail(self) -> str:
        try:
            text = self._stderr_path.read_bytes()[-STDERR_TAIL:].decode("utf-8", "replace")
        except OSError:
            return ""
        return " | ".join(line for line in text.strip().splitlines()[-10:] if line.strip())

    # SlaveLike ---------------------------------------------------------------------------

    def variable(self, name: str, *, settable: bool = False) -> FmuVariable:
        """As Slave.variable: checked here, so a wrong port is refused before the child
        binds anything."""
        var = self.info.variable(name)
        if var is None:
            raise CosimRunError(f"{self.label} has no variable {name!r}")
        if var.type in ("String", "Binary", "Clock") or var.shape:
            raise CosimRunError(
                f"{self.label}: {name} is a {var.type}{' array' if var.shape else ''}; "
                "only scalar numbers and Booleans can be connected or recorded"
            )
        if settable and var.causality not in ("input", "parameter"):
            raise CosimRunError(f"{self.label}: {name} is an {var.causality}, not an input")
        return var

    def port(self, name: str, *, into: bool) -> tuple[Group, int]:
        """Grouped as a Slave groups them (by type, in the order asked), so the child's
        groups, asked for in the same order, match these buffer for buffer."""
        var = self.variable(name, settable=into)
        groups = self._inputs if into else self._outputs
        group = groups.setdefault(var.type, Group(var.type))
        if name not in group.names:
            group.names.append(name)
            group.vrs.append(var.value_reference)
            self._ports.append((name, into))
        return group, group.names.index(name)

    def bind(self) -> None:
        for groups in (self._outputs, self._inputs):
            for type_, group in groups.items():
                dtype = self._dtypes.get(type_)
                if dtype is None:
                    raise CosimRunError(
                        f"{self.label}: variables of type {type_} cannot be exchanged"
                    )
                group.buffer = np.zeros(len(group.vrs), dtype=dtype)
        self._call(p.PORTS, orjson.dumps(self._ports))

    def set_start_values(self, values: list[tuple[str, Scalar]]) -> None:
        self._call(p.START, orjson.dumps(values))

    def enter_initialization(self, start: float, stop: float | None) -> None:
        self._call(p.ENTER, p.TIMES.pack(start, np.nan if stop is None else stop))

    def exit_initialization(self) -> None:
        self._call(p.EXIT)

    def read(self) -> None:
        data = self._call(p.READ)
        offset = 0
        for group in self._outputs.values():
            buffer = group.buffer
            buffer[:] = np.frombuffer(data, buffer.dtype, len(buffer), offset)
            offset += buffer.nbytes

    def write(self) -> None:
        self._call(p.WRITE, b"".join(g.buffer.tobytes() for g in self._inputs.values()))

    def step(self, t: float, h: float) -> float:
        reached: float = p.TIME.unpack(self._call(p.STEP, p.TIMES.pack(t, h)))[0]
        return reached

    def save_state(self) -> object:
        if not self.can_rollback:
            raise CosimRunError(f"{self.label} cannot save its state (canGetAndSetFMUstate)")
        key: int = p.STATE.unpack(self._call(p.SAVE))[0]
        return key

    def restore_state(self, state: object) -> None:
        self._call(p.RESTORE, p.STATE.pack(_key(state)))

    def free_state(self, state: object) -> None:
        self._call(p.FREE, p.STATE.pack(_key(state)))

    def close(self) -> None:
        """Ask the child to terminate and free its FMU and exit; kill it if it does not
        within CLOSE_TIMEOUT_S. Never raises."""
        proc = self.proc if hasattr(self, "proc") else None
        if proc is None:
            return
        try:
            if proc.poll() is None:
                with contextlib.suppress(OSError, ValueError):
                    self._requests.write(p.HEADER.pack(p.CLOSE, 0))
                    self._requests.flush()
                    _wait_readable(self._answers, CLOSE_TIMEOUT_S)
                try:
                    proc.wait(CLOSE_TIMEOUT_S)
                except subprocess.TimeoutExpired:
                    _log.warning("%s: its process did not close in time; killed", self.label)
                    proc.kill()
                    proc.wait(KILL_TIMEOUT_S)
        except Exception as err:  # closing must not hide the run's own error
            _log.warning("%s: closing its process failed: %s", self.label, err)
        finally:
            for pipe in (self._requests, self._answers):
                with contextlib.suppress(OSError, ValueError):
                    pipe.close()


def _key(state: object) -> int:
    if not isinstance(state, int):
        raise TypeError(f"not a state saved by IsolatedSlave.save_state: {state!r}")
    return state


def _wait_readable(stream: Any, timeout: float) -> None:
    """Until the child answers (or closes its end), at most `timeout` seconds."""
    with contextlib.suppress(OSError, ValueError):
        select.select([stream.fileno()], [], [], timeout)
