"""Column-wise blocks: one signal's samples from one batch, packed for storage.

A block keeps its times sorted (stable, so equal times keep arrival order) and carries a
summary (count, min, max, sum, first, last) so aggregations can use whole blocks unread, where
its extremes are (`sketch.py`) so min/max downsampling can too, and a hash of its times so a
stream's samples can be counted without reading its blocks (`times_hash`).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

import numpy as np
import numpy.typing as npt
import orjson

from twinlink.domain.samples import Value
from twinlink.store.sqlite.history.sketch import summarize

TIME_DTYPE = np.dtype("<i8")
VALUE_DTYPES: dict[str, np.dtype[Any]] = {  # numeric kinds as stored
    "i": np.dtype("<i8"),
    "f": np.dtype("<f8"),
    "b": np.dtype("u1"),
}


@dataclass(slots=True)
class Block:
    signal: str
    t0: int
    t1: int
    n: int
    kind: str
    vmin: float | None
    vmax: float | None
    vsum: float | None
    first_v: Value
    last_v: Value
    times: bytes
    vals: bytes
    tmin: int | None = None  # numeric kinds only: the time of vmin (the first of equals)
    tmax: int | None = None
    sketch: bytes | None = None  # numeric blocks of more than sketch.CHUNK samples
    times_hash: int | None = None  # see `times_hash`


# Named columns: the table gained tmin, tmax and sketch (migration 0003) and times_hash
# (0004) after the others.
INSERT_BLOCK = (
    "INSERT INTO blocks (series_id, t0, t1, n, kind, vmin, vmax, vsum, first_v, last_v, "
    "times, vals, tmin, tmax, sketch, times_hash) "
    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"
)
HASH_BITS = 62
_HASH_MASK = (1 << HASH_BITS) - 1
_MIX = (0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9, 0x94D049BB133111EB)  # splitmix64


def block_row(series_id: int, b: Block) -> tuple[Any, ...]:
    """The parameters of INSERT_BLOCK for one block."""
    return (series_id, b.t0, b.t1, b.n, b.kind, b.vmin, b.vmax, b.vsum, _sql(b.first_v),
            _sql(b.last_v), b.times, b.vals, b.tmin, b.tmax, b.sketch, b.times_hash)  # fmt: skip


def times_hash(times: npt.NDArray[np.int64]) -> int:
    """The sum (mod 2^62) of splitmix64 of each time: equal for equal multisets of times,
    and additive, so the hash of a signal's times is the sum of its blocks' (also after
    compaction merged some). Different multisets collide with a chance of about 2^-62."""
    x = times.view(np.uint64)
    x = x + np.uint64(_MIX[0])  # uint64 arrays wrap around silently, as splitmix64 wants
    x = (x ^ (x >> np.uint64(30))) * np.uint64(_MIX[1])
    x = (x ^ (x >> np.uint64(27))) * np.uint64(_MIX[2])
    x ^= x >> np.uint64(31)
    return int(x.sum(dtype=np.uint64)) & _HASH_MASK


def _sql(value: Value) -> Value:
    return int(value) if isinstance(value, bool) else value


def split_signals(
    times: list[int], values: list[dict[str, Value]]
) -> dict[str, tuple[list[int], list[Value]]]:
    """Turn row-wise samples into one (times, values) column pair per signal."""
    columns: dict[str, tuple[list[int], list[Value]]] = {}
    for time_ns, row in zip(times, values, strict=True):
        for name, value in row.items():
            column = columns.get(name)
            if column is None:
                column = columns[name] = ([], [])
            column[0].append(time_ns)
            column[1].append(value)
    return columns


def kind_of(values: list[Value]) -> str:
    kinds = {type(values[0])} if len(values) == 1 else set(map(type, values))
    if kinds == {int}:
        return "i"
    if kinds == {bool}:
        return "b"
    if kinds <= {int, float}:
        return "f"
    return "j"


# Below this many samples a block is packed with plain Python: numpy's cost per call (about
# 1 us, a dozen calls a block) is most of the work for the one-sample batches of slow
# devices (a 2 000-device fleet at 2 samples/s writes 8 000 such blocks a second). The
# results are the same bytes and numbers: numpy also sums fewer than 8 values in order.
SMALL_BLOCK = 8
_M64 = (1 << 64) - 1
_PACK = {"i": "q", "f": "d"}


def _mix(t: int) -> int:
    x = (t + _MIX[0]) & _M64
    x = ((x ^ (x >> 30)) * _MIX[1]) & _M64
    x = ((x ^ (x >> 27)) * _MIX[2]) & _M64
    return x ^ (x >> 31)


def _encode_small(signal: str, kind: str, times: list[int], values: list[Value]) -> Block:
    """`encode` of fewer than SMALL_BLOCK samples, without numpy."""
    n = len(times)
    if n > 1 and any(a > b for a, b in pairwise(times)):
        order = sorted(range(n), key=times.__getitem__)  # stable, as numpy's argsort
        times = [times[i] for i in order]
        values = [values[i] for i in order]
    vmin = vmax = vsum = tmin = tmax = None
    if kind == "j":
        blob = orjson.dumps(values)
    else:
        floats = [float(v) for v in values]
        blob = bytes(values) if kind == "b" else struct.pack(f"<{n}{_PACK[kind]}", *values)  # type: ignore[arg-type]
        if n == 1:
            vmin = vmax = floats[0]
            vsum = 0.0 + vmin  # as numpy sums: -0.0 becomes 0.0
            tmin = tmax = times[0]
        else:
            vsum = 0.0
            for x in floats:
                vsum += x
            low = min(range(n), key=floats.__getitem__)  # the first of equals, as argmin
            high = max(range(n), key=floats.__getitem__)
            vmin, vmax, tmin, tmax = floats[low], floats[high], times[low], times[high]
    return Block(
        signal=signal,
        t0=times[0],
        t1=times[-1],
        n=n,
        kind=kind,
        vmin=vmin,
        vmax=vmax,
        vsum=vsum,
        first_v=values[0],
        last_v=values[-1],
        times=struct.pack(f"<{n}q", *times),
        vals=blob,
        tmin=tmin,
        tmax=tmax,
        times_hash=(_mix(times[0] & _M64) if n == 1 else sum(_mix(t & _M64) for t in times))
        & _HASH_MASK,
    )


def encode(signal: str, times: list[int], values: list[Value]) -> Block:
    kind = kind_of(values)
    if len(times) < SMALL_BLOCK:
        return _encode_small(signal, kind, times, values)
    t = np.asarray(times, dtype=TIME_DTYPE)
    order = None
    if t.size > 1 and bool(np.any(t[1:] < t[:-1])):
        order = np.argsort(t, kind="stable")
        t = t[order]
        values = [values[i] for i in order]
    tmin = tmax = sketch_blob = None
    if kind == "j":
        blob = orjson.dumps(values)
        vmin = vmax = vsum = None
    else:
        v = np.asarray(values, dtype=VALUE_DTYPES[kind])
        blob = v.tobytes()
        vsum = float(v.sum(dtype=np.float64))
        floats = v.astype(np.float64, copy=False)
        vmin, vmax, tmin, tmax, sketch_blob = summarize(t, floats)
    return Block(
        signal=signal,
        t0=int(t[0]),
        t1=int(t[-1]),
        n=int(t.size),
        kind=kind,
        vmin=vmin,
        vmax=vmax,
        vsum=vsum,
        first_v=values[0],
        last_v=values[-1],
        times=t.tobytes(),
        vals=blob,
        tmin=tmin,
        tmax=tmax,
        sketch=sketch_blob,
        times_hash=times_hash(t),
    )


def decode_times(blob: bytes) -> npt.NDArray[np.int64]:
    return np.frombuffer(blob, dtype=TIME_DTYPE)


def decode_values(kind: str, blob: bytes) -> npt.NDArray[Any]:
    """Numeric kinds as numpy arrays (bool as bool); JSON blocks as an object array."""
    if kind == "j":
        return np.asarray(orjson.loads(blob), dtype=object)
    array: npt.NDArray[Any] = np.frombuffer(blob, dtype=VALUE_DTYPES[kind])
    return array.astype(bool) if kind == "b" else array
