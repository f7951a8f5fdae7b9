"""The complementary filter against a plain loop over equation 4.2, for any split of the data."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from twinlink.processors.blueprint import Batch, Context
from twinlink.processors.blueprints.complementary import (
    ComplementaryFilter,
    ComplementaryParams,
)

T0 = 1_700_000_000_000_000_000


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def loop(times: np.ndarray, rate: np.ndarray, acc: np.ndarray, k: float) -> list[float]:
    """Equation 4.2, one sample at a time."""
    theta = [float(acc[0])]
    for i in range(1, len(times)):
        dt = (int(times[i]) - int(times[i - 1])) / 1e9
        theta.append(k * (theta[-1] + rate[i] * dt) + (1 - k) * acc[i])
    return theta


def data(n: int = 2000, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    steps = rng.integers(5_000_000, 15_000_000, n)  # uneven spacing, 5..15 ms
    times = T0 + np.cumsum(steps)
    true = 0.3 * np.sin(np.cumsum(steps) / 1e9)
    rate = np.gradient(true, np.cumsum(steps) / 1e9) + 0.01  # a biased gyro
    acc = true + rng.normal(0, 0.05, n)  # a noisy accelerometer
    return times, rate, acc


def run(bp: ComplementaryFilter, batches: list[Batch]) -> Batch:
    bp.start()
    return Batch.concat([o for b in batches if (o := bp.process(b)) is not None])


def test_matches_the_equation_for_any_split(tmp_path: Path) -> None:
    times, rate, acc = data()
    want = loop(times, rate, acc, 0.85)
    p = ComplementaryParams(rate="gyro", angle="acc")
    bp = ComplementaryFilter(p, ctx(tmp_path))
    assert bp.inputs() == ["gyro", "acc"] and bp.outputs() == ["angle_filtered"]
    whole = run(bp, [Batch.of(times, gyro=rate, acc=acc)])
    np.testing.assert_array_equal(whole.times, times)
    np.testing.assert_allclose(whole["angle_filtered"], want, rtol=1e-12, atol=1e-15)
    rng = np.random.default_rng(5)
    cuts = [0, 1, 2, *sorted(rng.choice(np.arange(3, 2000), 30, replace=False)), 2000]
    batches = [Batch.of(times[a:b], gyro=rate[a:b], acc=acc[a:b]) for a, b in pairwise(cuts)]
    split = run(ComplementaryFilter(p, ctx(tmp_path)), batches)
    np.testing.assert_array_equal(split["angle_filtered"], whole["angle_filtered"])


@pytest.mark.parametrize("k", [0.0, 0.5, 0.98, 1.0])
def test_weights(tmp_path: Path, k: float) -> None:
    times, rate, acc = data(300, seed=2)
    p = ComplementaryParams(rate="r", angle="a", output="theta", k=k)
    out = run(ComplementaryFilter(p, ctx(tmp_path)), [Batch.of(times, r=rate, a=acc)])
    np.testing.assert_allclose(out["theta"], loop(times, rate, acc, k), rtol=1e-12, atol=1e-15)
    if k == 0.0:
        np.testing.assert_array_equal(out["theta"], acc)


def test_a_missing_signal_holds_its_latest_value(tmp_path: Path) -> None:
    nan = np.nan
    times = T0 + np.array([0, 10, 20, 30, 40]) * 1_000_000
    rate = np.array([nan, 1.0, nan, 2.0, nan])
    acc = np.array([0.5, nan, 0.7, nan, nan])
    p = ComplementaryParams(rate="r", angle="a", k=0.5)
    bp = ComplementaryFilter(p, ctx(tmp_path))
    out = run(bp, [Batch.of(times[:3], r=rate[:3], a=acc[:3]), Batch.of(times[3:], r=rate[3:])])
    # The first row has no rate yet, the last row has no value at all; between them the
    # rate and the angle are held.
    held_rate, held_acc = np.array([1.0, 1.0, 2.0]), np.array([0.5, 0.7, 0.7])
    np.testing.assert_array_equal(out.times, times[1:4])
    np.testing.assert_allclose(out["angle_filtered"], loop(times[1:4], held_rate, held_acc, 0.5))
    assert bp.process(Batch.of([T0 + 10**9], other=[1.0])) is None


def test_reconfigure_keeps_theta(tmp_path: Path) -> None:
    times, rate, acc = data(100, seed=3)
    p = ComplementaryParams(rate="r", angle="a", k=0.9)
    bp = ComplementaryFilter(p, ctx(tmp_path))
    bp.start()
    first = bp.process(Batch.of(times[:50], r=rate[:50], a=acc[:50]))
    assert first is not None
    assert bp.reconfigure(p.model_copy(update={"k": 0.6})) is True
    second = bp.process(Batch.of(times[50:], r=rate[50:], a=acc[50:]))
    assert second is not None
    theta = float(first["angle_filtered"][-1])
    for i in range(50, 100):
        dt = (int(times[i]) - int(times[i - 1])) / 1e9
        theta = 0.6 * (theta + rate[i] * dt) + 0.4 * acc[i]
        assert second["angle_filtered"][i - 50] == pytest.approx(theta, rel=1e-12)


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ({"rate": "r", "angle": "a", "k": 1.5}, "k"),
        ({"rate": "r", "angle": "a", "k": -0.1}, "k"),
        ({"rate": "r", "angle": "r"}, "different"),
        ({"rate": "r"}, "angle"),
        ({"rate": "r", "angle": "a", "K": 0.5}, "K"),
    ],
)
def test_bad_params(values: dict, match: str) -> None:
    with pytest.raises(ValidationError, match=match):
        ComplementaryParams(**values)
