"""Butterworth filters: low-pass, high-pass, band-pass and band-stop.

Each signal is filtered by second-order sections (`scipy.signal.butter(..., output="sos")`)
whose state is carried from batch to batch, so a signal split into any number of batches is
filtered exactly as if it came in one. The state starts as the steady state for the first value
(`sosfilt_zi` scaled by it), so a signal that starts away from zero has no start-up transient.
"""

from __future__ import annotations

from typing import Any, ClassVar, TypeVar

import numpy as np
import numpy.typing as npt
from pydantic import Field, model_validator
from scipy import signal as sps  # type: ignore[import-untyped]

from twinlink.processors.blueprint import (
    MAX_RATE_HZ,
    Batch,
    Blueprint,
    BlueprintError,
    Context,
    Names,
    Params,
)

Array = npt.NDArray[np.float64]


class FilterParams(Params):
    """What every Butterworth filter takes; the subclasses add the cut-off frequencies."""

    signals: Names = Field(min_length=1, description="The signals to filter.")
    order: int = Field(
        4,
        ge=1,
        le=10,
        description="Filter order: higher is a steeper roll-off (and more delay). "
        "A band filter has twice this many poles.",
    )
    sample_rate_hz: float = Field(
        gt=0,
        le=MAX_RATE_HZ,
        description="The sampling rate the filter is designed for, in Hz. Samples are treated "
        "as evenly spaced at this rate, whatever their timestamps say.",
    )
    suffix: str = Field(
        "",
        description="Appended to each signal name to name its output; empty: the output has "
        "the signal's own name.",
    )

    def edges(self) -> list[float]:
        """The cut-off frequencies in Hz."""
        raise NotImplementedError


class CutoffParams(FilterParams):
    cutoff_hz: float = Field(
        gt=0,
        le=MAX_RATE_HZ,
        description="Cut-off frequency in Hz (-3 dB); below half the sample rate.",
    )

    def edges(self) -> list[float]:
        return [self.cutoff_hz]


class BandParams(FilterParams):
    low_hz: float = Field(gt=0, le=MAX_RATE_HZ, description="Lower edge of the band in Hz (-3 dB).")
    high_hz: float = Field(
        gt=0,
        le=MAX_RATE_HZ,
        description="Upper edge of the band in Hz (-3 dB); below half the sample rate.",
    )

    @model_validator(mode="after")
    def _ordered(self) -> BandParams:
        if self.low_hz >= self.high_hz:
            raise ValueError(f"low_hz ({self.low_hz}) must be below high_hz ({self.high_hz})")
        return self

    def edges(self) -> list[float]:
        return [self.low_hz, self.high_hz]


def design(params: FilterParams, btype: str) -> Any:
    """Second-order sections for these parameters; BlueprintError when a cut-off is too high."""
    nyquist = params.sample_rate_hz / 2
    for f in params.edges():
        if f >= nyquist:
            raise BlueprintError(
                f"cut-off {f:g} Hz must be below the Nyquist frequency {nyquist:g} Hz "
                f"(half the sample rate {params.sample_rate_hz:g} Hz)"
            )
    edges = params.edges()
    wn = edges[0] if len(edges) == 1 else edges
    return sps.butter(params.order, wn, btype=btype, fs=params.sample_rate_hz, output="sos")


FP = TypeVar("FP", bound=FilterParams)


class _Butterworth(Blueprint[FP]):
    btype: ClassVar[str] = ""
    keeps_state = True

    def __init__(self, params: FP, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._sos = design(params, self.btype)
        self._zi: dict[str, Array] = {}

    @classmethod
    def check(cls, params: Any) -> None:
        design(params, cls.btype)  # a cut-off at or above Nyquist is refused here

    def inputs(self) -> list[str]:
        return list(self.params.signals)

    def outputs(self) -> list[str]:
        return [s + self.params.suffix for s in self.params.signals]

    def describe(self) -> dict[str, Any]:
        return {"sections": int(self._sos.shape[0]), "edges_hz": self.params.edges()}

    def process(self, batch: Batch) -> Batch | None:
        out: dict[str, Array] = {}
        for name in self.params.signals:
            x = batch.columns.get(name)
            if x is not None:
                out[name + self.params.suffix] = self._filter(name, x)
        if not out:
            return None
        keep = np.zeros(len(batch), dtype=bool)
        for y in out.values():
            keep |= ~np.isnan(y)
        if not keep.any():
            return None
        if keep.all():
            return batch.with_columns(out)
        return Batch(batch.times[keep], {k: v[keep] for k, v in out.items()})

    def _filter(self, name: str, x: Array) -> Array:
        """Filters the finite values of `x`, carrying the state; NaN where `x` has none."""
        ok = np.isfinite(x)
        y = np.full(x.shape, np.nan)
        if not ok.any():
            return y
        values = x[ok] if not ok.all() else x
        zi = self._zi.get(name)
        if zi is None:
            zi = sps.sosfilt_zi(self._sos) * values[0]
        filtered, self._zi[name] = sps.sosfilt(self._sos, values, zi=zi)
        y[ok] = filtered
        return y

    def reconfigure(self, params: FP) -> bool:
        """Keeps the filter state when the signals and the order are unchanged (new cut-offs,
        sample rate or suffix only redesign the coefficients); otherwise asks for a restart."""
        if params.signals != self.params.signals or params.order != self.params.order:
            return False
        self._sos = design(params, self.btype)
        self.params = params
        return True


class LowPass(_Butterworth[CutoffParams]):
    """Low-pass filter (Butterworth)

    Passes frequencies below the cut-off and attenuates those above it; smooths noise.
    Samples are treated as evenly spaced at `sample_rate_hz`; missing values are skipped
    and the filter keeps its state over them.
    """

    name = "lowpass"
    Params = CutoffParams
    btype = "lowpass"


class HighPass(_Butterworth[CutoffParams]):
    """High-pass filter (Butterworth)

    Passes frequencies above the cut-off and removes slow drift and offsets below it.
    Samples are treated as evenly spaced at `sample_rate_hz`; missing values are skipped
    and the filter keeps its state over them.
    """

    name = "highpass"
    Params = CutoffParams
    btype = "highpass"


class BandPass(_Butterworth[BandParams]):
    """Band-pass filter (Butterworth)

    Passes frequencies between `low_hz` and `high_hz` and attenuates the rest.
    Samples are treated as evenly spaced at `sample_rate_hz`; missing values are skipped
    and the filter keeps its state over them.
    """

    name = "bandpass"
    Params = BandParams
    btype = "bandpass"


class BandStop(_Butterworth[BandParams]):
    """Band-stop filter (Butterworth)

    Removes frequencies between `low_hz` and `high_hz` (a hum or a resonance) and passes
    the rest. Samples are treated as evenly spaced at `sample_rate_hz`; missing values are
    skipped and the filter keeps its state over them.
    """

    name = "bandstop"
    Params = BandParams
    btype = "bandstop"
