"""A complementary filter fusing a gyroscope's rate with an accelerometer's angle."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from pydantic import Field, model_validator
from scipy import signal as sps  # type: ignore[import-untyped]

from twinlink.processors.blueprint import Batch, Blueprint, Context, Params

Array = npt.NDArray[np.float64]


class ComplementaryParams(Params):
    rate: str = Field(description="The signal of the gyroscope's angular rate, in rad/s.")
    angle: str = Field(
        description="The signal of the angle computed from the accelerometer, in rad."
    )
    output: str = Field("angle_filtered", min_length=1, description="Name of the output signal.")
    k: float = Field(
        0.85,
        ge=0,
        le=1,
        description="K, the weight of the integrated gyroscope rate; 1 - K is the weight of "
        "the accelerometer angle. Higher trusts the gyroscope more (less noise, more drift).",
    )

    @model_validator(mode="after")
    def _distinct(self) -> ComplementaryParams:
        if self.rate == self.angle:
            raise ValueError("rate and angle must be different signals")
        return self


def hold(x: Array, carry: float) -> Array:
    """`x` with each missing value replaced by the latest value before it (`carry` at first)."""
    ok = np.isfinite(x)
    if ok.all():
        return x
    last = np.maximum.accumulate(np.where(ok, np.arange(x.shape[0]), -1))
    return np.where(last >= 0, x[last], carry)


class ComplementaryFilter(Blueprint[ComplementaryParams]):
    """Complementary filter (gyroscope + accelerometer angle)

    Fuses a gyroscope's angular rate, accurate short-term but drifting, with the angle from an
    accelerometer, noisy but without drift (NTNU thesis, equation 4.2):

        theta[i+1] = K * (theta[i] + rate * dt) + (1 - K) * theta_acc

    `rate` and `theta_acc` are the values of sample i+1 and `dt` is the time between the two
    samples, from their timestamps. The first sample gives theta = theta_acc. When a sample has
    only one of the two signals, the latest value of the other is used. The output is made at
    each sample once both signals have had a value.
    """

    name = "complementary"
    Params = ComplementaryParams
    keeps_state = True

    def __init__(self, params: ComplementaryParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._theta: float | None = None
        self._time = 0
        self._rate = np.nan
        self._acc = np.nan

    def inputs(self) -> list[str]:
        return [self.params.rate, self.params.angle]

    def outputs(self) -> list[str]:
        return [self.params.output]

    def process(self, batch: Batch) -> Batch | None:
        nan = np.full(len(batch), np.nan)
        rate = batch.columns.get(self.params.rate, nan)
        acc = batch.columns.get(self.params.angle, nan)
        rate_held, acc_held = hold(rate, self._rate), hold(acc, self._acc)
        if len(batch):
            self._rate, self._acc = float(rate_held[-1]), float(acc_held[-1])
        ready = (np.isfinite(rate) | np.isfinite(acc)) & np.isfinite(rate_held)
        ready &= np.isfinite(acc_held)
        index = np.flatnonzero(ready)
        if index.shape[0] == 0:
            return None
        times = batch.times[index]
        theta = self._update(times, rate_held[index], acc_held[index])
        return Batch(times, {self.params.output: theta})

    def _update(self, times: npt.NDArray[np.int64], rate: Array, acc: Array) -> Array:
        k = self.params.k
        if self._theta is None:
            self._theta, self._time = float(acc[0]), int(times[0])
            if times.shape[0] == 1:
                return acc[:1]
            return np.concatenate([acc[:1], self._update(times[1:], rate[1:], acc[1:])])
        dt = np.diff(times, prepend=self._time) / 1e9
        u = k * rate * dt + (1 - k) * acc
        theta, _ = sps.lfilter([1.0], [1.0, -k], u, zi=[k * self._theta])
        self._theta, self._time = float(theta[-1]), int(times[-1])
        return np.asarray(theta, dtype=np.float64)
