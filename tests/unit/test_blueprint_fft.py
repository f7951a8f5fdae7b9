"""The spectrum blueprint on synthetic sines, against numpy/scipy spectra of the same frames."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError
from scipy import signal as sps

from twinlink.processors.blueprint import Batch, Context
from twinlink.processors.blueprints.fft import Spectrum, SpectrumParams

FS = 1000.0
T0 = 1_700_000_000_000_000_000


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def sine(f: float, amplitude: float, n: int = 4096, offset: float = 0.0) -> Batch:
    t = np.arange(n) / FS
    x = offset + amplitude * np.sin(2 * np.pi * f * t + 0.4)
    return Batch.of(T0 + (t * 1e9).astype(np.int64), x=x)


def run(p: SpectrumParams, batches: list[Batch], tmp_path: Path) -> Batch:
    bp = Spectrum(p, ctx(tmp_path))
    bp.start()
    return Batch.concat([o for b in batches if (o := bp.process(b)) is not None])


@pytest.mark.parametrize("window", ["hann", "hamming", "rectangular"])
@pytest.mark.parametrize("f", [50.0, 123.4, 250.49, 333.3])
def test_a_sine_gives_its_frequency_and_amplitude(tmp_path: Path, window: str, f: float) -> None:
    p = SpectrumParams(signals=["x"], window_samples=1024, sample_rate_hz=FS, window=window)
    out = run(p, [sine(f, 2.5, offset=10.0)], tmp_path)
    assert len(out) == 4
    df = FS / 1024
    assert np.all(np.abs(out["x.peak_hz"] - f) < df)  # within a bin (in fact far closer)
    np.testing.assert_allclose(out["x.peak_amplitude"], 2.5, rtol=0.02)
    frames = np.asarray(sine(f, 2.5, offset=10.0)["x"]).reshape(4, 1024)
    np.testing.assert_allclose(out["x.rms"], np.sqrt(np.mean(frames**2, axis=1)), rtol=1e-12)


def test_bins_match_scipy_windows_and_numpy_fft(tmp_path: Path) -> None:
    batch = sine(62.5, 1.0, n=512)
    p = SpectrumParams(
        signals=["x"], window_samples=256, hop_samples=64, sample_rate_hz=FS, bins=20
    )
    out = run(p, [batch], tmp_path)
    x = batch["x"]
    w = sps.get_window("hann", 256)  # periodic, as for spectral analysis
    starts = range(0, 512 - 256 + 1, 64)
    np.testing.assert_array_equal(out.times, [batch.times[s + 255] for s in starts])
    for row, s in enumerate(starts):
        amp = np.abs(np.fft.rfft(x[s : s + 256] * w)) * 2 / w.sum()
        amp[0] /= 2
        got = [out[f"x.amp.{k}"][row] for k in range(20)]
        np.testing.assert_allclose(got, amp[:20], rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(out["x.df_hz"], FS / 256)
    assert out["x.amp.16"][0] == pytest.approx(1.0)  # 62.5 Hz is bin 16 exactly


@pytest.mark.parametrize("hop", [None, 100, 300, 1000])
def test_the_same_frames_for_any_split(tmp_path: Path, hop: int | None) -> None:
    rng = np.random.default_rng(hop or 0)
    n = 5000
    times = T0 + np.arange(n, dtype=np.int64) * 1_000_000
    x, y = rng.normal(size=n), rng.normal(size=n)
    y[rng.random(n) < 0.3] = np.nan
    p = SpectrumParams(
        signals=["x", "y"], window_samples=256, hop_samples=hop, sample_rate_hz=FS, bins=3
    )
    whole = run(p, [Batch.of(times, x=x, y=y)], tmp_path)
    cuts = [0, 0, 1, *sorted(rng.integers(1, n, 30).tolist()), n]
    split = run(p, [Batch.of(times[a:b], x=x[a:b], y=y[a:b]) for a, b in pairwise(cuts)], tmp_path)
    np.testing.assert_array_equal(split.times, whole.times)
    for name in whole.columns:
        np.testing.assert_array_equal(split[name], whole[name], err_msg=name)
    step = hop or 256
    x_ends = times[255::step][: (n - 256) // step + 1]
    assert np.isin(x_ends, whole.times).all()
    assert np.isfinite(whole["x.rms"]).sum() == len(x_ends)
    ys = np.flatnonzero(np.isfinite(y))  # y's frames hold y's own values
    y_ends = times[ys[255::step][: (len(ys) - 256) // step + 1]]
    np.testing.assert_array_equal(whole.times[np.isfinite(whole["y.rms"])], y_ends)
    first = y[ys[:256]]
    assert whole["y.rms"][whole.times == y_ends[0]][0] == pytest.approx(np.sqrt(np.mean(first**2)))


def test_outputs_and_nothing_before_a_full_frame(tmp_path: Path) -> None:
    p = SpectrumParams(signals=["x"], window_samples=64, sample_rate_hz=FS, bins=2)
    bp = Spectrum(p, ctx(tmp_path))
    assert bp.inputs() == ["x"]
    assert bp.outputs() == [
        "x.peak_hz",
        "x.peak_amplitude",
        "x.rms",
        "x.df_hz",
        "x.amp.0",
        "x.amp.1",
    ]
    assert bp.process(sine(10, 1, n=63)) is None
    assert bp.process(Batch.of([T0 + 10**9], other=[1.0])) is None


def test_reconfigure_keeps_the_collected_values(tmp_path: Path) -> None:
    p = SpectrumParams(signals=["x"], window_samples=512, sample_rate_hz=FS)
    batch = sine(100, 1.0, n=1024)
    bp = Spectrum(p, ctx(tmp_path))
    assert bp.process(batch.take(slice(0, 400))) is None
    assert bp.reconfigure(p.model_copy(update={"window": "rectangular", "bins": 1})) is True
    out = bp.process(batch.take(slice(400, 1024)))
    assert out is not None and len(out) == 2
    frame = batch["x"][:512]
    assert out["x.amp.0"][0] == pytest.approx(abs(frame.mean()), abs=1e-12)
    assert out["x.peak_amplitude"][0] == pytest.approx(1.0, rel=0.02)
    assert bp.reconfigure(p.model_copy(update={"window_samples": 256})) is False
    assert bp.reconfigure(p.model_copy(update={"signals": ["x", "y"]})) is False


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ({"window_samples": 1000}, "power of two"),
        ({"window_samples": 8}, "window_samples"),
        ({"window_samples": 131072}, "window_samples"),
        ({"window_samples": 64, "bins": 34}, "at most"),
        ({"hop_samples": 0}, "hop_samples"),
        ({"window": "blackman"}, "window"),
        ({"sample_rate_hz": 0}, "sample_rate_hz"),
        ({"signals": []}, "signals"),
    ],
)
def test_bad_params(values: dict[str, Any], match: str) -> None:
    base: dict[str, Any] = {"signals": ["x"], "sample_rate_hz": FS}
    with pytest.raises(ValidationError, match=match):
        SpectrumParams(**(base | values))
