"""Block sketches: where the extremes of a block are, chunk by chunk.

A numeric block stores the time of its smallest and of its largest value (`tmin`, `tmax`, the
first of equals). A block of more than `CHUNK` samples also stores a sketch: per chunk of
`CHUNK` samples (the last one shorter), the times of its first and last sample and its
smallest and largest value with their times. A min/max downsample takes every chunk that lies
inside one bucket from the sketch (about 1/40 of the bytes of the samples) and reads samples
only of the chunks that bucket edges cut.

Blocks written before sketches existed (migration 0003) have neither; readers sketch them as
they read them.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

CHUNK = 128
# Per chunk, six little-endian 8-byte fields: the times of its first and last sample, of its
# smallest and of its largest value (the first of equals), then those values (float64).
FIELDS = ("first", "last", "t_low", "t_high", "low", "high")
Table = npt.NDArray[np.int64]  # (chunks, 6); the value fields hold float64 bits


def chunks(n: int) -> int:
    return -(-n // CHUNK)


def is_sketch(blob: bytes | None, n: int) -> bool:
    """Whether `blob` is a sketch of a block of `n` samples."""
    return blob is not None and len(blob) == 8 * len(FIELDS) * chunks(n)


def summarize(
    times: npt.NDArray[np.int64], values: npt.NDArray[np.float64]
) -> tuple[float, float, int, int, bytes | None]:
    """(vmin, vmax, tmin, tmax, sketch) of a block's samples sorted by time; no sketch for
    a block of one chunk."""
    if times.size <= CHUNK:
        low, high = int(values.argmin()), int(values.argmax())
        return float(values[low]), float(values[high]), int(times[low]), int(times[high]), None
    out = table(times, values)
    floats = out.view(np.float64)
    # The first chunk holding the extreme holds its first occurrence.
    low, high = int(floats[:, 4].argmin()), int(floats[:, 5].argmax())
    return (
        float(floats[low, 4]), float(floats[high, 5]), int(out[low, 2]), int(out[high, 3]),
        out.tobytes(),
    )  # fmt: skip


def table(times: npt.NDArray[np.int64], values: npt.NDArray[np.float64]) -> Table:
    """The sketch of samples sorted by time, as a (chunks, 6) table."""
    n = times.size
    k = chunks(n)
    full = n - n % CHUNK
    body = values[:full].reshape(-1, CHUNK)  # a view: no copy of the values
    low = np.empty(k, dtype=np.intp)
    high = np.empty(k, dtype=np.intp)
    low[: full // CHUNK] = body.argmin(axis=1)
    high[: full // CHUNK] = body.argmax(axis=1)
    if full < n:
        low[-1] = values[full:].argmin()
        high[-1] = values[full:].argmax()
    starts = np.arange(0, n, CHUNK)
    low += starts
    high += starts
    out = np.empty((k, len(FIELDS)), dtype="<i8")
    out[:, 0] = times[::CHUNK]
    out[: full // CHUNK, 1] = times[CHUNK - 1 : full : CHUNK]
    out[-1, 1] = times[-1]
    out[:, 2] = times[low]
    out[:, 3] = times[high]
    floats = out.view("<f8")
    floats[:, 4] = values[low]
    floats[:, 5] = values[high]
    return out


def columns(blob: bytes) -> tuple[Table, npt.NDArray[np.float64]]:
    """Sketches (joined) as (chunks, 6) views: as int64 (the times) and as float64 (the
    values)."""
    ints = np.frombuffer(blob, dtype="<i8").reshape(-1, len(FIELDS))
    return ints, ints.view("<f8")
