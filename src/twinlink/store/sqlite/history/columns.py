"""Decoded columns: blocks turned into sorted numpy arrays of times and values.

Blocks may overlap in time (late or resent data); a stable sort by time merges them and keeps
samples with equal times in block order.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt
import orjson

from twinlink.store.sqlite.history.codec import TIME_DTYPE, decode_times, decode_values

Times = npt.NDArray[np.int64]
Floats = npt.NDArray[np.float64]
Values = npt.NDArray[Any]

EMPTY_TIMES: Times = np.empty(0, dtype=TIME_DTYPE)
EMPTY_FLOATS: Floats = np.empty(0, dtype=np.float64)
_NUMERIC_DTYPES: dict[str, np.dtype[Any]] = {
    "i": np.dtype("<i8"),
    "f": np.dtype("<f8"),
    "b": np.dtype("u1"),
}


def concat_values(arrays: Sequence[Values]) -> Values:
    """One array of the values of several blocks. Blocks of different kinds meet as Python
    objects, so an integer stays an integer and a bool a bool."""
    if len(arrays) == 1:
        return arrays[0]
    if len({a.dtype for a in arrays}) == 1:
        return np.concatenate(arrays)
    return np.concatenate([a.astype(object) for a in arrays])


def merge_sorted(
    times: Times, values: Values, more_times: Times, more_values: Values
) -> tuple[Times, Values]:
    """Two sorted columns as one; equal times keep `times` first."""
    if times.size == 0:
        return more_times, more_values
    t = np.concatenate([times, more_times])
    v = concat_values([values, more_values])
    if more_times.size and more_times[0] < times[-1]:
        order = np.argsort(t, kind="stable")
        t, v = t[order], v[order]
    return t, v


def clip(times: Times, values: Values, start: int, end: int) -> tuple[Times, Values]:
    """The part of a sorted column with start <= time <= end."""
    lo = int(np.searchsorted(times, start, side="left")) if times[0] < start else 0
    hi = int(np.searchsorted(times, end, side="right")) if times[-1] > end else times.size
    return times[lo:hi], values[lo:hi]


def numeric_block(kind: str, times: bytes, vals: bytes) -> tuple[Times, Floats]:
    """A block's samples as floats (bools as 0 and 1); text values of a JSON block are left
    out."""
    t = decode_times(times)
    if kind != "j":
        return t, decode_values(kind, vals).astype(np.float64, copy=False)
    raw = orjson.loads(vals)
    keep = [i for i, x in enumerate(raw) if not isinstance(x, str)]
    return t[keep], np.asarray([float(raw[i]) for i in keep], dtype=np.float64)


NumericBlock = tuple[int, int, str, bytes, bytes]  # t0, t1, kind, times, vals


def numeric_column(blocks: Sequence[NumericBlock], start: int, end: int) -> tuple[Times, Floats]:
    """The numeric samples in [start, end] of `blocks` (in t0 order), sorted by time."""
    if not blocks:
        return EMPTY_TIMES, EMPTY_FLOATS
    kinds = {b[2] for b in blocks}
    if len(kinds) == 1 and "j" not in kinds:
        # One join of the blobs and one view: no per-block work for the common case.
        dtype = _NUMERIC_DTYPES[next(iter(kinds))]
        t = np.frombuffer(b"".join(b[3] for b in blocks), dtype=TIME_DTYPE)
        raw = np.frombuffer(b"".join(b[4] for b in blocks), dtype=dtype)
        v = raw.astype(np.float64, copy=False)
    else:
        parts = [numeric_block(*b[2:]) for b in blocks]
        t = np.concatenate([p[0] for p in parts])
        v = np.concatenate([p[1] for p in parts])
    # Each block is sorted; the whole is sorted unless a block starts before one ends.
    ends = np.maximum.accumulate(np.fromiter((b[1] for b in blocks), np.int64, len(blocks)))
    starts = np.fromiter((b[0] for b in blocks), np.int64, len(blocks))
    if bool(np.any(starts[1:] < ends[:-1])):
        order = np.argsort(t, kind="stable")
        t, v = t[order], v[order]
    if t.size:
        t, v = clip(t, v, start, end)
    return t, v


def numeric_blocks(
    blocks: Sequence[tuple[str, bytes, bytes]], exact: bool
) -> tuple[Times, Values, npt.NDArray[np.intp]]:
    """The numeric samples of many blocks (kind, times, vals) in one piece, in block order,
    and how many each block gave. `exact`: the blocks are all integer blocks, and their
    values stay int64; else they are floats (bools as 0 and 1; text of JSON blocks left out).
    """
    if not blocks:
        empty: Values = np.empty(0, dtype=np.int64 if exact else np.float64)
        return EMPTY_TIMES, empty, np.empty(0, dtype=np.intp)
    kinds = {b[0] for b in blocks}
    if "j" not in kinds:
        sizes = np.fromiter((len(b[1]) // 8 for b in blocks), np.intp, len(blocks))
        times = np.frombuffer(b"".join(b[1] for b in blocks), dtype=TIME_DTYPE)
        if len(kinds) == 1:
            raw = np.frombuffer(b"".join(b[2] for b in blocks), dtype=_NUMERIC_DTYPES[kinds.pop()])
            return times, raw if exact else raw.astype(np.float64, copy=False), sizes
        values = np.empty(times.size, dtype=np.float64)
        kind_of = np.asarray([b[0] for b in blocks])
        for kind in kinds:
            which = kind_of == kind
            part = b"".join(b[2] for b, w in zip(blocks, which.tolist(), strict=True) if w)
            values[np.repeat(which, sizes)] = np.frombuffer(part, dtype=_NUMERIC_DTYPES[kind])
        return times, values, sizes
    parts = [numeric_block(*b) for b in blocks]  # JSON blocks: few, decoded one by one
    sizes = np.fromiter((p[0].size for p in parts), np.intp, len(parts))
    return (
        np.concatenate([p[0] for p in parts]),
        np.concatenate([p[1] for p in parts]),
        sizes,
    )
