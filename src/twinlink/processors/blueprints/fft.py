"""Spectrum of frames of samples: the peak frequency and amplitude, the RMS, amplitude bins.

The window functions are generalised cosine windows a0 - a1 cos(2 pi n / N) (periodic, as for
spectral analysis), whose transform has a closed form. That gives a table for the tone
correction: the ratio of the peak bin to its larger neighbour tells how far between bins the
tone lies (delta, in bins), and the window's response at delta corrects the amplitude.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import numpy.typing as npt
from pydantic import Field, field_validator, model_validator

from twinlink.processors.blueprint import MAX_RATE_HZ, Batch, Blueprint, Context, Names, Params

Array = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
WindowName = Literal["hann", "hamming", "rectangular"]
COSINE: dict[str, tuple[float, float]] = {
    "hann": (0.5, 0.5),
    "hamming": (0.54, 0.46),
    "rectangular": (1.0, 0.0),
}
CHUNK = 1 << 22  # samples transformed at once, at most


class SpectrumParams(Params):
    signals: Names = Field(min_length=1, description="The signals to analyse.")
    window_samples: int = Field(
        1024, ge=16, le=65536, description="Frame length in samples: a power of two."
    )
    hop_samples: int | None = Field(
        None,
        ge=1,
        le=10_000_000,
        description="Samples from the start of one frame to the start of the next; empty: "
        "the frame length (frames side by side). Less overlaps the frames.",
    )
    window: WindowName = Field("hann", description="Window function applied to each frame.")
    sample_rate_hz: float = Field(
        gt=0,
        le=MAX_RATE_HZ,
        description="Sampling rate in Hz. A signal's values are treated as evenly spaced at "
        "this rate, whatever their timestamps say.",
    )
    bins: int = Field(
        0,
        ge=0,
        le=65536 // 2 + 1,
        description="Also output the first this many amplitude bins ({signal}.amp.{k}, at "
        "k * df_hz) and the bin width {signal}.df_hz; 0: none.",
    )

    @field_validator("window_samples")
    @classmethod
    def _power_of_two(cls, n: int) -> int:
        if n & (n - 1):
            raise ValueError(f"window_samples must be a power of two, not {n}")
        return n

    @model_validator(mode="after")
    def _bins_fit(self) -> SpectrumParams:
        if self.bins > self.window_samples // 2 + 1:
            raise ValueError(f"bins must be at most window_samples / 2 + 1 = {self.n_bins}")
        return self

    @property
    def n_bins(self) -> int:
        return self.window_samples // 2 + 1

    @property
    def hop(self) -> int:
        return self.hop_samples or self.window_samples


def dirichlet(delta: Array, n: int) -> npt.NDArray[np.complex128]:
    """Sum over k < n of exp(-2 pi i delta k / n): a rectangular window's response."""
    num = 1 - np.exp(-2j * np.pi * delta)
    den = 1 - np.exp(-2j * np.pi * delta / n)
    tiny = np.abs(den) < 1e-12
    return np.where(tiny, n, num / np.where(tiny, 1, den))


class ToneTable:
    """For a window: the tone offset from the neighbour ratio and the response at an offset."""

    def __init__(self, window: str, n: int) -> None:
        a0, a1 = COSINE[window]
        self.window = a0 - a1 * np.cos(2 * np.pi * np.arange(n) / n)
        self.gain = a0 * n  # the window's sum: a tone on a bin has |X| = amplitude * gain / 2
        self.spectrum = np.fft.rfft(self.window)
        offsets = np.linspace(0.0, 1.0, 4001)
        response = np.abs(
            a0 * dirichlet(offsets, n)
            - a1 / 2 * (dirichlet(offsets - 1, n) + dirichlet(offsets + 1, n))
        ) / (a0 * n)
        half = offsets <= 0.5
        self.delta = offsets[half]
        self.response = response[half]
        ratio = response[::-1][half] / response[half]  # W(1 - delta) / W(delta)
        self.ratio = np.maximum.accumulate(ratio)

    def correct(self, peak: Array, neighbour: Array) -> tuple[Array, Array]:
        """Offset of the tone from the peak bin (0..0.5) and the amplitude correction."""
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(peak > 0, neighbour / peak, 0.0)
        delta = np.interp(ratio, self.ratio, self.delta)
        return delta, 1.0 / np.interp(delta, self.delta, self.response)


def analyse(frames: Array, table: ToneTable, df: float, bins: int) -> dict[str, Array]:
    """The outputs of each frame (one per row). The peak is sought in the spectrum of the frame
    less its mean, so an offset (leaking into the bins next to DC) is no peak."""
    mean = np.mean(frames, axis=1)
    transform = np.fft.rfft((frames - mean[:, None]) * table.window, axis=1)
    spectrum = np.abs(transform)
    rows = np.arange(frames.shape[0])
    k = 1 + np.argmax(spectrum[:, 1:], axis=1)
    last = spectrum.shape[1] - 1
    left = np.where(k > 1, spectrum[rows, k - 1], 0.0)
    right = np.where(k < last, spectrum[rows, np.minimum(k + 1, last)], 0.0)
    delta, gain = table.correct(spectrum[rows, k], np.maximum(left, right))
    side = np.where(right >= left, 1.0, -1.0)
    scale = np.where(k < last, 2.0, 1.0) / table.gain  # the Nyquist bin is not doubled
    out = {
        "peak_hz": (k + side * delta) * df,
        "peak_amplitude": spectrum[rows, k] * scale * gain,
        "rms": np.sqrt(np.mean(frames * frames, axis=1)),
    }
    if bins:
        # The spectrum with the mean put back: transform + mean * the window's own transform.
        raw = np.abs(transform[:, :bins] + mean[:, None] * table.spectrum[:bins])
        raw *= 2.0 / table.gain
        raw[:, 0] /= 2
        if bins > last:
            raw[:, last] /= 2
        out["df_hz"] = np.full(frames.shape[0], df)
        out.update({f"amp.{b}": raw[:, b] for b in range(bins)})
    return out


class Spectrum(Blueprint[SpectrumParams]):
    """Spectrum (FFT): peak frequency, peak amplitude, RMS

    Cuts each signal into frames of `window_samples` values, one every `hop_samples`, applies
    the window function and computes the amplitude spectrum. For each frame, at the time of
    its last sample: `{signal}.peak_hz` and `{signal}.peak_amplitude` of the largest peak
    (interpolated between bins and corrected for the window, so a sine of amplitude A gives
    A; the frame's mean is removed first, so an offset is no peak), `{signal}.rms` of the
    frame's values, and with `bins` > 0 the first amplitude bins `{signal}.amp.{k}` (bin 0 is
    the mean) and the bin width `{signal}.df_hz`. Missing values are skipped: a frame holds
    the signal's values, treated as evenly spaced at `sample_rate_hz`.
    """

    name = "fft"
    Params = SpectrumParams
    keeps_state = True

    def __init__(self, params: SpectrumParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._table = ToneTable(params.window, params.window_samples)
        self._times: dict[str, Ints] = {}
        self._values: dict[str, Array] = {}
        self._skip: dict[str, int] = {}  # values still to pass before the next frame starts

    def inputs(self) -> list[str]:
        return list(self.params.signals)

    def outputs(self) -> list[str]:
        names = ["peak_hz", "peak_amplitude", "rms"]
        if self.params.bins:
            names += ["df_hz", *(f"amp.{b}" for b in range(self.params.bins))]
        return [f"{s}.{n}" for s in self.params.signals for n in names]

    def reconfigure(self, params: SpectrumParams) -> bool:
        """Keeps the collected values when the signals and the frame length are unchanged."""
        if (params.signals, params.window_samples) != (
            self.params.signals,
            self.params.window_samples,
        ):
            return False
        self._table = ToneTable(params.window, params.window_samples)
        self.params = params
        return True

    def process(self, batch: Batch) -> Batch | None:
        results: list[tuple[str, Ints, dict[str, Array]]] = []
        for s in self.params.signals:
            x = batch.columns.get(s)
            if x is not None:
                ok = np.isfinite(x)
                times, frames = self._frames(s, batch.times[ok], x[ok])
                if times.shape[0]:
                    results.append((s, times, self._analyse(frames)))
        return merge(results)

    def _frames(self, s: str, times: Ints, values: Array) -> tuple[Ints, Array]:
        """The frames completed by these values (and their end times); keeps the rest."""
        skip = min(self._skip.get(s, 0), values.shape[0])
        self._skip[s] = self._skip.get(s, 0) - skip
        t = np.concatenate([self._times.get(s, np.empty(0, np.int64)), times[skip:]])
        v = np.concatenate([self._values.get(s, np.empty(0)), values[skip:]])
        n, size, hop = v.shape[0], self.params.window_samples, self.params.hop
        if n < size:
            self._times[s], self._values[s] = t, v
            return t[:0], np.empty((0, size))
        count = (n - size) // hop + 1
        frames = np.lib.stride_tricks.sliding_window_view(v, size)[::hop][:count]
        ends = t[size - 1 :: hop][:count]
        rest = count * hop
        self._times[s], self._values[s] = t[rest:], v[rest:]
        self._skip[s] += max(rest - n, 0)
        return ends, frames

    def _analyse(self, frames: Array) -> dict[str, Array]:
        df = self.params.sample_rate_hz / self.params.window_samples
        step = max(CHUNK // self.params.window_samples, 1)
        parts = [
            analyse(frames[i : i + step], self._table, df, self.params.bins)
            for i in range(0, frames.shape[0], step)
        ]
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def merge(results: list[tuple[str, Ints, dict[str, Array]]]) -> Batch | None:
    """One batch of every signal's frames: rows at the union of their times."""
    if not results:
        return None
    times = np.unique(np.concatenate([t for _, t, _ in results]))
    columns: dict[str, Array] = {}
    for s, t, values in results:
        at = np.searchsorted(times, t)
        for name, v in values.items():
            col = np.full(times.shape[0], np.nan)
            col[at] = v
            columns[f"{s}.{name}"] = col
    return Batch(times, columns)
