"""A blueprint: the moving average of the last `window` samples of each signal.

Its state (the last samples of each signal) carries over from batch to batch, so the output
is the same however the input was split into batches. It is computed for a whole batch at
once with numpy, never sample by sample in Python.

A blueprint imports nothing from the server but the blueprint API, and is registered by one
line in pyproject.toml:

    [project.entry-points."twinlink.blueprints"]
    moving_average = "twinlink_example_plugins.moving_average:MovingAverage"
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from pydantic import Field

from twinlink.processors.blueprint import Batch, Blueprint, Context, Names, Params

Array = npt.NDArray[np.float64]


class MovingAverageParams(Params):
    signals: Names = Field(min_length=1, description="The signals to average.")
    window: int = Field(
        5, ge=1, le=100_000, description="How many samples, the newest included, are averaged."
    )
    suffix: str = Field(
        "_avg", min_length=1, max_length=32, description="Each output is `<signal><suffix>`."
    )


class MovingAverage(Blueprint[MovingAverageParams]):
    """Moving average

    The mean of each signal's last `window` samples (fewer at the start), at each sample. A
    sample without the signal (NaN) is left out of its mean, and gives no output for it.
    """

    name = "moving_average"
    Params = MovingAverageParams

    def __init__(self, params: MovingAverageParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        # The last window - 1 values of each signal seen, the carry into the next batch.
        self._tail: dict[str, Array] = {s: np.empty(0) for s in params.signals}

    def inputs(self) -> list[str]:
        return list(self.params.signals)

    def outputs(self) -> list[str]:
        return [s + self.params.suffix for s in self.params.signals]

    def process(self, batch: Batch) -> Batch | None:
        if len(batch) == 0:
            return None
        out: dict[str, Array] = {}
        for signal in self.params.signals:
            column = batch.columns.get(signal)
            if column is None:
                continue
            out[signal + self.params.suffix] = self._average(signal, column)
        return batch.with_columns(out) if out else None

    def _average(self, signal: str, column: Array) -> Array:
        present = np.isfinite(column)
        values = np.concatenate([self._tail[signal], column[present]])
        keep = self.params.window - 1
        self._tail[signal] = values[len(values) - keep :] if keep else values[:0]
        # Means of the windows ending at each new value, from running sums.
        sums = np.concatenate([[0.0], np.cumsum(values)])
        ends = np.arange(len(values) - int(present.sum()), len(values)) + 1
        starts = np.maximum(ends - self.params.window, 0)
        result = np.full(column.shape, np.nan)
        result[present] = (sums[ends] - sums[starts]) / (ends - starts)
        return result
