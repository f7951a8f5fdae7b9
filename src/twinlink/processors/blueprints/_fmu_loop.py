"""The hot loops of the FMU blueprint: per sample, or on a fixed step grid.

Inputs arrive as a C-contiguous (samples, inputs) float64 array; the engine gets the address
of a row, so no value is converted or allocated per step. Unchanged input rows are not set
again. Outputs are read into a preallocated array by the OutputReader.
"""

from __future__ import annotations

import numpy as np

from ._fmu_cs import Engine
from ._fmu_fmi import Terminated
from ._fmu_io import OutputReader


def changed_rows(u: np.ndarray) -> np.ndarray:
    """True for the rows of `u` that differ from the row before (and for the first row)."""
    changed = np.ones(u.shape[0], dtype=bool)
    if u.shape[1] == 0:
        changed[:] = False
    elif u.shape[0] > 1:
        changed[1:] = np.any(u[1:] != u[:-1], axis=1)
    return changed


def run_samples(engine: Engine, reader: OutputReader, t: np.ndarray, u: np.ndarray) -> None:
    """For each sample: set its inputs, step from the previous sample time to its time (no
    step if that is not later), read the outputs. One output row per sample; when the FMU
    terminates, Terminated with the rows read, the last one at the FMU's end."""
    reader.target(len(t))
    set_inputs, advance, read = engine.set_inputs, engine.advance, reader.read
    base, stride = u.ctypes.data, u.strides[0]
    for k, (tk, changed) in enumerate(zip(t.tolist(), changed_rows(u).tolist(), strict=True)):
        if changed:
            set_inputs(base + k * stride)
        if tk > engine.time:
            try:
                advance(tk)
            except Terminated as end:
                read(k)
                end.rows = k + 1
                raise
        read(k)


def run_fixed(
    engine: Engine, reader: OutputReader, h: float, done: int, t: np.ndarray, u: np.ndarray
) -> np.ndarray:
    """Steps of `h` on the grid n * h (n > `done` steps already taken) up to each sample time,
    holding the latest inputs; a sample's inputs apply from its time on. Returns the step
    numbers taken; the reader has one output row per step, read at the step's end. When the
    FMU terminates, Terminated with the rows read, the last one at the FMU's end."""
    targets = np.floor(t / h + 1e-9).astype(np.int64) if len(t) else np.empty(0, np.int64)
    last = max(done, int(targets.max())) if len(t) else done
    reader.target(last - done)
    set_inputs, advance, read = engine.set_inputs, engine.advance, reader.read
    base, stride = u.ctypes.data, u.strides[0]
    step = done
    for k, (target, changed) in enumerate(
        zip(targets.tolist(), changed_rows(u).tolist(), strict=True)
    ):
        while step < target:
            step += 1
            try:
                advance(step * h)
            except Terminated as end:
                read(step - done - 1)
                end.rows = step - done
                raise
            read(step - done - 1)
        if changed:
            set_inputs(base + k * stride)
    return np.arange(done + 1, step + 1, dtype=np.int64)
