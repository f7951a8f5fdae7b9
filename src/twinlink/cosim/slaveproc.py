"""The child process of an isolated instance (isolated.py): `python -m twinlink.cosim.slaveproc`.

It runs one Slave (or MeSlave) and answers the parent's requests, one frame each way
(frames.py), on its stdin and stdout. Values travel as the raw bytes of the numpy buffers,
the rest as JSON (orjson) or struct-packed numbers.

The FMU must not write into the frames: the process's own fd 1 is pointed at stderr (a
printf in C code lands in the parent's log file) before any FMU is loaded, and the frames go
through a duplicate of the original stdout.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import IO, Any

import numpy as np
import orjson

from . import frames as f
from .kinds import open_in_process
from .protocol import SlaveLike
from .slaves import CosimRunError, FmuTerminated, Group

PARENT_POLL_S = 1.0


class _Child:
    def __init__(self) -> None:
        self.slave: SlaveLike | None = None
        self.outputs: list[Group] = []
        self.inputs: list[Group] = []
        self.states: dict[int, object] = {}

    def handle(self, op: int, payload: bytes) -> bytes:
        if op == f.OPEN:
            return self._open(orjson.loads(payload))
        slave = self.slave
        assert slave is not None, "OPEN comes first"
        if op == f.PORTS:
            self._ports(slave, orjson.loads(payload))
        elif op == f.START:
            slave.set_start_values([(name, value) for name, value in orjson.loads(payload)])
        elif op == f.ENTER:
            start, stop = f.TIMES.unpack(payload)
            slave.enter_initialization(start, None if np.isnan(stop) else stop)
        elif op == f.EXIT:
            slave.exit_initialization()
        elif op == f.READ:
            slave.read()
            return b"".join(g.buffer.tobytes() for g in self.outputs)
        elif op == f.WRITE:
            offset = 0
            for g in self.inputs:
                g.buffer[:] = np.frombuffer(payload, g.buffer.dtype, len(g.buffer), offset)
                offset += g.buffer.nbytes
            slave.write()
        elif op == f.STEP:
            return f.TIME.pack(slave.step(*f.TIMES.unpack(payload)))
        elif op == f.SAVE:
            key = max(self.states, default=0) + 1
            self.states[key] = slave.save_state()
            return f.STATE.pack(key)
        elif op == f.RESTORE:
            slave.restore_state(self.states[f.STATE.unpack(payload)[0]])
        elif op == f.FREE:
            slave.free_state(self.states.pop(f.STATE.unpack(payload)[0]))
        else:
            raise ValueError(f"unknown request {op}")
        return b""

    def _open(self, spec: dict[str, Any]) -> bytes:
        self.slave = open_in_process(spec["name"], Path(spec["fmu"]), Path(spec["workdir"]))
        return orjson.dumps({"can_rollback": self.slave.can_rollback})

    def _ports(self, slave: SlaveLike, ports: list[tuple[str, bool]]) -> None:
        outputs: dict[int, Group] = {}
        inputs: dict[int, Group] = {}
        for name, into in ports:  # the parent's order: the same groups, in the same order
            group, _ = slave.port(name, into=into)
            (inputs if into else outputs).setdefault(id(group), group)
        slave.bind()
        self.outputs, self.inputs = list(outputs.values()), list(inputs.values())


def _answer(out: IO[bytes], status: int, payload: bytes) -> None:
    out.write(f.HEADER.pack(status, len(payload)) + payload)
    out.flush()


def serve(requests: IO[bytes], answers: IO[bytes]) -> None:
    """Answer requests until CLOSE or the parent goes away; the slave is closed either way."""
    child = _Child()
    try:
        while True:
            try:
                op, size = f.HEADER.unpack(f.read_exactly(requests, f.HEADER.size))
                payload = f.read_exactly(requests, size)
            except EOFError:
                return  # the parent is gone
            if op == f.CLOSE:
                break
            try:
                _answer(answers, f.OK, child.handle(op, payload))
            except FmuTerminated as done:
                _answer(answers, f.TERMINATED, orjson.dumps([str(done), done.time]))
            except CosimRunError as err:
                _answer(answers, f.RUN_ERROR, str(err).encode())
            except Exception as err:  # a bug, not the FMU's: the parent names the instance
                _answer(answers, f.FAILED, f"{type(err).__name__}: {err}".encode())
    finally:
        if child.slave is not None:
            child.slave.close()
    with contextlib.suppress(OSError):
        _answer(answers, f.OK, b"")


def _watch_parent(parent: int) -> None:
    """End this process once its parent is gone, even while an FMU's step runs (stdin's EOF
    is seen only between requests). Not prctl's PDEATHSIG: it fires when the parent's
    *thread* that started this process ends, and a parent may open a session in a thread
    and step it in another."""
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_S)
    os._exit(1)


def main() -> None:
    # Ctrl-C and a stop's SIGTERM reach the whole process group: the parent decides when
    # this one ends (it closes it, or kills it after a grace period).
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    threading.Thread(target=_watch_parent, args=(os.getppid(),), daemon=True).start()
    answers = os.fdopen(os.dup(1), "wb")
    requests = os.fdopen(os.dup(0), "rb")
    os.dup2(2, 1)  # what the FMU prints goes to stderr, not into the frames
    sys.stdout = sys.stderr
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    os.close(devnull)
    serve(requests, answers)


if __name__ == "__main__":
    main()
