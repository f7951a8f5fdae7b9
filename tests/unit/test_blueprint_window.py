"""Window aggregates against a plain computation over each window, for any split of the data."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from twinlink.processors.blueprint import Batch, Context
from twinlink.processors.blueprints.window import WindowAggregate, WindowParams, range_extreme

T0 = 1_700_000_000_000_000_000
MS = 1_000_000
ALL = ["mean", "rms", "min", "max", "p2p", "std", "count"]


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def data(n: int = 1500, seed: int = 0) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    rng = np.random.default_rng(seed)
    times = T0 + np.cumsum(rng.integers(1, 20, n)) * MS  # uneven, 1..19 ms
    a = rng.normal(5.0, 2.0, n)
    b = rng.normal(-1.0, 0.5, n)
    a[rng.random(n) < 0.1] = np.nan
    b[rng.random(n) < 0.5] = np.nan
    b[200:400] = np.nan  # a long gap: empty time windows
    return times, {"a": a, "b": b}


def stats(v: np.ndarray) -> dict[str, float]:
    if v.size == 0:
        return {f: (0.0 if f == "count" else np.nan) for f in ALL}
    return {
        "mean": float(np.mean(v)),
        "rms": float(np.sqrt(np.mean(v * v))),
        "min": float(np.min(v)),
        "max": float(np.max(v)),
        "p2p": float(np.ptp(v)),
        "std": float(np.std(v)),
        "count": float(v.size),
    }


def naive(times: np.ndarray, cols: dict[str, np.ndarray], p: WindowParams) -> Batch:
    """Every window computed on its own, the slow and obvious way."""
    rows = np.flatnonzero(np.any([np.isfinite(c) for c in cols.values()], axis=0))
    if p.hop_s == 0:
        ends = [(int(times[r]), r) for r in rows]
    else:
        hop = round(p.hop_s * 1e9)
        closing = sorted({-(-int(times[r]) // hop) * hop for r in rows})[:-1]
        ends = [(e, int(np.searchsorted(times, e, side="right")) - 1) for e in closing]
    out: dict[str, list[float]] = {f"{s}.{f}": [] for s in cols for f in p.functions}
    for s, x in cols.items():
        present = np.flatnonzero(np.isfinite(x))
        for end, last in ends:
            idx = present[: np.searchsorted(present, last, side="right")]
            if p.window_samples is not None:
                idx = idx[-p.window_samples :]
            else:
                idx = idx[times[idx] > end - round((p.window_s or 0) * 1e9)]
            got = stats(x[idx])
            for f in p.functions:
                out[f"{s}.{f}"].append(got[f])
    return Batch.of([e for e, _ in ends], **out)


def run(p: WindowParams, batches: list[Batch], tmp_path: Path) -> Batch:
    bp = WindowAggregate(p, ctx(tmp_path))
    bp.start()
    outs = [o for b in batches if (o := bp.process(b)) is not None]
    return Batch.concat(outs) if outs else Batch.empty(bp.outputs())


def random_split(times: np.ndarray, cols: dict[str, np.ndarray], seed: int) -> list[Batch]:
    rng = np.random.default_rng(seed)
    cuts = sorted({0, 1, len(times), *rng.integers(0, len(times), 40).tolist()})
    cuts = [0, *cuts]  # an empty batch first
    return [Batch.of(times[a:b], **{s: c[a:b] for s, c in cols.items()}) for a, b in pairwise(cuts)]


def assert_same(got: Batch, want: Batch, exact: bool = False) -> None:
    np.testing.assert_array_equal(got.times, want.times)
    assert set(got.columns) == set(want.columns)
    for name in want.columns:
        if exact or name.endswith((".count", ".min", ".max")):
            np.testing.assert_array_equal(got[name], want[name], err_msg=name)
        else:
            np.testing.assert_allclose(got[name], want[name], rtol=1e-9, atol=1e-9, err_msg=name)


CASES: list[dict[str, Any]] = [
    {"window_s": 0.25},
    {"window_samples": 16},
    {"window_s": 0.5, "hop_s": 0.1},
    {"window_s": 0.05, "hop_s": 0.2},
    {"window_samples": 7, "hop_s": 0.13},
    {"window_samples": 1},
]


@pytest.mark.parametrize("window", CASES)
def test_matches_each_window_computed_alone_for_any_split(
    tmp_path: Path, window: dict[str, Any]
) -> None:
    times, cols = data()
    p = WindowParams(signals=["a", "b"], functions=ALL, **window)
    want = naive(times, cols, p)
    assert len(want) > 10
    whole = run(p, [Batch.of(times, **cols)], tmp_path)
    assert_same(whole, want)
    for seed in (1, 2):
        assert_same(run(p, random_split(times, cols, seed), tmp_path), want)
    one_by_one = [
        Batch.of(times[i : i + 1], **{s: c[i : i + 1] for s, c in cols.items()}) for i in range(300)
    ]
    assert_same(
        run(p, one_by_one, tmp_path), naive(times[:300], {s: c[:300] for s, c in cols.items()}, p)
    )


def test_empty_windows_and_absent_columns(tmp_path: Path) -> None:
    p = WindowParams(signals=["a", "b"], functions=["mean", "count", "max"], window_s=0.015)
    times = T0 + np.array([0, 10, 20, 50]) * MS
    got = run(
        p, [Batch.of(times[:2], a=[1.0, 3.0]), Batch.of(times[2:], a=[np.nan, 8.0])], tmp_path
    )
    np.testing.assert_array_equal(got.times, times[[0, 1, 3]])
    np.testing.assert_array_equal(got["a.mean"], [1.0, 2.0, 8.0])
    np.testing.assert_array_equal(got["a.count"], [1.0, 2.0, 1.0])
    np.testing.assert_array_equal(got["b.count"], [0.0, 0.0, 0.0])
    assert np.isnan(got["b.mean"]).all() and np.isnan(got["b.max"]).all()


def test_hop_outputs_at_interval_ends_once_closed(tmp_path: Path) -> None:
    p = WindowParams(signals=["x"], functions=["mean", "count"], window_s=1.0, hop_s=1.0)
    bp = WindowAggregate(p, ctx(tmp_path))
    s = 1_000_000_000
    base = T0 // s * s
    assert bp.process(Batch.of([base + s // 4, base + s // 2], x=[1.0, 2.0])) is None
    assert bp.process(Batch.of([base + s], x=[3.0])) is None  # on the end: still open
    out = bp.process(Batch.of([base + s + 1, base + 5 * s], x=[10.0, 20.0]))
    assert out is not None
    assert out.times.tolist() == [base + s, base + 2 * s]  # the empty intervals give nothing
    assert out["x.mean"].tolist() == [2.0, 10.0] and out["x.count"].tolist() == [3.0, 1.0]


def test_std_is_precise_on_a_large_offset(tmp_path: Path) -> None:
    rng = np.random.default_rng(4)
    x = 1e6 + rng.normal(0, 1e-3, 5000)
    times = T0 + np.arange(5000) * MS
    p = WindowParams(signals=["x"], functions=["std", "mean"], window_samples=100)
    got = run(p, [Batch.of(times, x=x)], tmp_path)
    want = np.array([np.std(x[max(i - 99, 0) : i + 1]) for i in range(5000)])
    np.testing.assert_allclose(got["x.std"][1:], want[1:], rtol=1e-3)
    assert got["x.std"][0] == 0.0


def test_range_extreme_against_a_loop() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(size=500)
    lo = rng.integers(0, 500, 300)
    hi = np.minimum(lo + rng.integers(0, 130, 300), 500)
    got = range_extreme(x, lo, hi, np.maximum)
    for i in range(300):
        assert got[i] == (
            x[lo[i] : hi[i]].max() if hi[i] > lo[i] else pytest.approx(np.nan, nan_ok=True)
        )


def test_reconfigure_keeps_the_tail_when_the_signals_stay(tmp_path: Path) -> None:
    times, cols = data(600, seed=7)
    p = WindowParams(signals=["a"], functions=["mean"], window_samples=20)
    bp = WindowAggregate(p, ctx(tmp_path))
    bp.start()
    bp.process(Batch.of(times[:300], a=cols["a"][:300]))
    new = p.model_copy(update={"functions": ["max", "count"], "hop_s": 0.05})
    assert bp.reconfigure(new) is True
    assert bp.outputs() == ["a.max", "a.count"]
    got = bp.process(Batch.of(times[300:], a=cols["a"][300:]))
    assert got is not None
    want = naive(times, {"a": cols["a"]}, new)
    later = want.times > times[299]
    assert_same(got, want.take(later), exact=True)
    assert bp.reconfigure(p.model_copy(update={"signals": ["a", "b"]})) is False


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ({"signals": ["x"]}, "exactly one"),
        ({"signals": ["x"], "window_s": 1, "window_samples": 5}, "exactly one"),
        ({"signals": ["x"], "window_s": 0}, "window_s"),
        ({"signals": ["x"], "window_samples": 0}, "window_samples"),
        ({"signals": ["x"], "window_s": 1, "hop_s": -1}, "hop_s"),
        ({"signals": ["x"], "window_s": 1, "functions": ["median"]}, "functions"),
        ({"signals": ["x"], "window_s": 1, "functions": []}, "functions"),
        ({"signals": [], "window_s": 1}, "signals"),
        ({"signals": ["x", "x"], "window_s": 1}, "twice"),
    ],
)
def test_bad_params(values: dict[str, Any], match: str) -> None:
    with pytest.raises(ValidationError, match=match):
        WindowParams(**values)


def test_schema_lists_the_functions() -> None:
    schema = WindowParams.model_json_schema()
    assert schema["properties"]["functions"]["items"]["enum"] == ALL
    assert all(prop.get("description") for prop in schema["properties"].values())
