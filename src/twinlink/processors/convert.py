"""Between the bus's sample batches (a dict per sample) and a blueprint's columns."""

from __future__ import annotations

import math
import time
from collections.abc import Collection

import numpy as np

from twinlink.domain.samples import SampleBatch, Value
from twinlink.processors.blueprint import Batch


def _number(value: Value | None) -> float:
    if value is None or isinstance(value, str):
        return math.nan
    return float(value)


def to_columns(batch: SampleBatch, signals: Collection[str] | None) -> Batch:
    """The numeric signals of `batch` in columns (all of them when `signals` is None)."""
    n = len(batch)
    if signals is None:
        names: dict[str, None] = {}
        for values in batch.values:
            names.update(dict.fromkeys(values))
        signals = list(names)
    columns = {
        name: np.fromiter((_number(v.get(name)) for v in batch.values), np.float64, n)
        for name in signals
    }
    return Batch(np.fromiter(batch.times, np.int64, n), columns)


def to_samples(out: Batch, twin_id: int, twin: str, stream: str, source: str) -> SampleBatch:
    """A blueprint's output as a sample batch; NaN means "no value" and is left out."""
    lists = {k: v.tolist() for k, v in out.columns.items()}
    values: list[dict[str, Value]] = [
        {k: column[i] for k, column in lists.items() if column[i] == column[i]}
        for i in range(len(out))
    ]
    return SampleBatch(
        twin_id=twin_id,
        twin=twin,
        stream=stream,
        times=out.times.tolist(),
        values=values,
        received_ns=time.time_ns(),
        source=source,
    )
