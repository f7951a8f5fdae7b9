"""Butterworth filter blueprints: batch-by-batch output must equal scipy's sosfilt over the
whole signal (started from the steady state of the first value), however the data are split."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError
from scipy import signal as sps

from twinlink.processors.blueprint import Batch, BlueprintError, Context
from twinlink.processors.blueprints.filters import (
    BandParams,
    BandPass,
    BandStop,
    CutoffParams,
    HighPass,
    LowPass,
)

FS = 1000.0
T0 = 1_700_000_000_000_000_000


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def signal(n: int = 4000, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    x = 3.0 + np.sin(2 * np.pi * 5 * t) + 0.5 * np.sin(2 * np.pi * 180 * t) + rng.normal(0, 0.1, n)
    return T0 + (t * 1e9).astype(np.int64), x


def reference(x: np.ndarray, order: int, wn: float | list[float], btype: str) -> np.ndarray:
    sos = sps.butter(order, wn, btype=btype, fs=FS, output="sos")
    y, _ = sps.sosfilt(sos, x, zi=sps.sosfilt_zi(sos) * x[0])
    return np.asarray(y)


def run(bp: LowPass | HighPass | BandPass | BandStop, batches: list[Batch]) -> Batch:
    bp.start()
    outs = [o for b in batches if (o := bp.process(b)) is not None]
    return Batch.concat(outs)


def splits(times: np.ndarray, x: np.ndarray, seed: int, name: str = "x") -> list[Batch]:
    rng = np.random.default_rng(seed)
    cuts = np.sort(rng.choice(np.arange(1, len(x)), size=25, replace=False))
    return [
        Batch.of(times[a:b], **{name: x[a:b]})
        for a, b in zip([0, *cuts], [*cuts, len(x)], strict=True)
    ]


@pytest.mark.parametrize(
    ("cls", "params", "wn", "btype"),
    [
        (LowPass, {"cutoff_hz": 20.0}, 20.0, "lowpass"),
        (HighPass, {"cutoff_hz": 50.0}, 50.0, "highpass"),
        (BandPass, {"low_hz": 100.0, "high_hz": 250.0}, [100.0, 250.0], "bandpass"),
        (BandStop, {"low_hz": 150.0, "high_hz": 210.0}, [150.0, 210.0], "bandstop"),
    ],
)
def test_matches_sosfilt_over_the_whole_signal_for_any_split(
    tmp_path: Path, cls: type, params: dict, wn: float | list[float], btype: str
) -> None:
    times, x = signal()
    p = cls.Params(signals=["x"], order=4, sample_rate_hz=FS, **params)
    want = reference(x, 4, wn, btype)
    whole = run(cls(p, ctx(tmp_path)), [Batch.of(times, x=x)])
    np.testing.assert_array_equal(whole.times, times)
    np.testing.assert_allclose(whole["x"], want, rtol=1e-12, atol=1e-12)
    for seed in (2, 3):
        split = run(cls(p, ctx(tmp_path)), splits(times, x, seed))
        np.testing.assert_array_equal(split.times, times)
        np.testing.assert_allclose(split["x"], want, rtol=1e-12, atol=1e-12)


def test_no_start_up_transient_on_a_constant(tmp_path: Path) -> None:
    p = CutoffParams(signals=["x"], cutoff_hz=10, order=6, sample_rate_hz=FS)
    times = T0 + np.arange(200, dtype=np.int64) * 1_000_000
    low = run(LowPass(p, ctx(tmp_path)), [Batch.of(times, x=np.full(200, 7.5))])
    np.testing.assert_allclose(low["x"], 7.5, rtol=1e-9)
    high = run(HighPass(p, ctx(tmp_path)), [Batch.of(times, x=np.full(200, 7.5))])
    np.testing.assert_allclose(high["x"], 0.0, atol=1e-9)


def test_missing_values_are_skipped_and_named_with_the_suffix(tmp_path: Path) -> None:
    times, x = signal(600)
    y = np.cos(np.arange(600) / 10.0)
    x[[0, 5, 6, 7, 300]] = np.nan
    y[100:] = np.nan
    p = CutoffParams(signals=["x", "y"], cutoff_hz=30, sample_rate_hz=FS, suffix=".lp")
    bp = LowPass(p, ctx(tmp_path))
    assert bp.inputs() == ["x", "y"] and bp.outputs() == ["x.lp", "y.lp"]
    out = run(bp, [Batch.of(times[:300], x=x[:300], y=y[:300]), Batch.of(times[300:], x=x[300:])])
    ok = ~np.isnan(x)
    rows = ok | ~np.isnan(y)
    np.testing.assert_array_equal(out.times, times[rows])
    np.testing.assert_allclose(out["x.lp"][ok[rows]], reference(x[ok], 4, 30.0, "lowpass"))
    assert np.isnan(out["x.lp"][~ok[rows]]).all()
    np.testing.assert_allclose(out["y.lp"][:100], reference(y[:100], 4, 30.0, "lowpass"))
    assert np.isnan(out["y.lp"][100:]).all()


def test_nothing_to_filter_gives_none(tmp_path: Path) -> None:
    bp = LowPass(CutoffParams(signals=["x"], cutoff_hz=5, sample_rate_hz=FS), ctx(tmp_path))
    bp.start()
    assert bp.process(Batch.of([T0, T0 + 1], other=[1.0, 2.0])) is None
    assert bp.process(Batch.of([T0 + 2], x=[np.nan])) is None
    assert bp.process(Batch.empty(["x"])) is None


def test_reconfigure_new_cutoff_keeps_the_state(tmp_path: Path) -> None:
    times, x = signal(1000)
    p = CutoffParams(signals=["x"], cutoff_hz=20, sample_rate_hz=FS)
    bp = LowPass(p, ctx(tmp_path))
    bp.start()
    first = bp.process(Batch.of(times[:500], x=x[:500]))
    assert first is not None
    assert bp.reconfigure(p.model_copy(update={"cutoff_hz": 40.0})) is True
    second = bp.process(Batch.of(times[500:], x=x[500:]))
    assert second is not None
    sos1 = sps.butter(4, 20.0, fs=FS, output="sos")
    sos2 = sps.butter(4, 40.0, fs=FS, output="sos")
    y1, zi = sps.sosfilt(sos1, x[:500], zi=sps.sosfilt_zi(sos1) * x[0])
    y2, _ = sps.sosfilt(sos2, x[500:], zi=zi)
    np.testing.assert_allclose(first["x"], y1, rtol=1e-12)
    np.testing.assert_allclose(second["x"], y2, rtol=1e-12)


def test_reconfigure_new_order_or_signals_asks_for_a_restart(tmp_path: Path) -> None:
    p = CutoffParams(signals=["x"], cutoff_hz=20, sample_rate_hz=FS)
    bp = LowPass(p, ctx(tmp_path))
    assert LowPass.keeps_state is True
    assert bp.reconfigure(p.model_copy(update={"order": 5})) is False
    assert bp.reconfigure(p.model_copy(update={"signals": ["x", "y"]})) is False
    with pytest.raises(BlueprintError, match="Nyquist"):
        bp.reconfigure(p.model_copy(update={"cutoff_hz": 600.0}))


@pytest.mark.parametrize("cutoff", [500.0, 800.0])
def test_cutoff_at_or_above_nyquist_is_refused(tmp_path: Path, cutoff: float) -> None:
    p = CutoffParams(signals=["x"], cutoff_hz=cutoff, sample_rate_hz=FS)
    with pytest.raises(BlueprintError, match=r"below the Nyquist frequency 500 Hz"):
        LowPass(p, ctx(tmp_path))
    band = BandParams(signals=["x"], low_hz=10, high_hz=cutoff, sample_rate_hz=FS)
    with pytest.raises(BlueprintError, match=r"500 Hz"):
        BandPass(band, ctx(tmp_path))


@pytest.mark.parametrize(
    ("cls", "values", "match"),
    [
        (CutoffParams, {"signals": [], "cutoff_hz": 1, "sample_rate_hz": FS}, "signals"),
        (CutoffParams, {"signals": ["x"], "cutoff_hz": 1, "sample_rate_hz": 0}, "sample_rate"),
        (CutoffParams, {"signals": ["x"], "cutoff_hz": 1}, "sample_rate_hz"),
        (
            CutoffParams,
            {"signals": ["x"], "cutoff_hz": 1, "sample_rate_hz": FS, "order": 11},
            "order",
        ),
        (CutoffParams, {"signals": ["x"], "cutoff_hz": 0, "sample_rate_hz": FS}, "cutoff_hz"),
        (CutoffParams, {"signals": ["x", "x"], "cutoff_hz": 1, "sample_rate_hz": FS}, "twice"),
        (CutoffParams, {"signals": ["x"], "cutof_hz": 1, "sample_rate_hz": FS}, "cutof_hz"),
        (BandParams, {"signals": ["x"], "low_hz": 9, "high_hz": 5, "sample_rate_hz": FS}, "below"),
    ],
)
def test_bad_params_are_validation_errors(cls: type, values: dict, match: str) -> None:
    with pytest.raises(ValidationError, match=match):
        cls(**values)


def test_schema_is_documented() -> None:
    schema = BandParams.model_json_schema()
    for field in ("signals", "order", "sample_rate_hz", "suffix", "low_hz", "high_hz"):
        assert schema["properties"][field]["description"]
    assert "evenly spaced" in schema["properties"]["sample_rate_hz"]["description"]
    assert schema["properties"]["order"]["maximum"] == 10
    assert (LowPass.__doc__ or "").startswith("Low-pass filter")
