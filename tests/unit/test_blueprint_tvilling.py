"""The Tvilling digital adapter: the example blueprints in tests/blueprints/tvilling_style, run
through the adapter, must give what the original platform's loop gives when driving P by hand."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from twinlink.processors.blueprint import Batch, BlueprintError, Context, describe_blueprint
from twinlink.processors.blueprints.tvilling import load_tvilling, tvilling_blueprint

FOLDER = Path(__file__).resolve().parents[1] / "blueprints" / "tvilling_style"
T0 = 1_700_000_000_000_000_000
MS = 1_000_000


def ctx(tmp_path: Path, spacing: float = 0.0) -> Context:
    return Context(
        processor="p", twin="t", files=tmp_path, workdir=tmp_path, step_spacing_s=spacing
    )


SMOOTHING = load_tvilling(FOLDER)
RAMP = load_tvilling(FOLDER / "ramp.py")


def by_hand(
    times: np.ndarray, x: np.ndarray, spacing_s: float, refs: list[int], **kwargs: Any
) -> tuple[list[int], list[list[float]]]:
    """The original platform's loop over a fresh P, one sample at a time."""
    start_params = kwargs.pop("start_params", {})
    p = SMOOTHING.p_class(**kwargs)
    p.start(start_time=0.0, **start_params)
    next_step, out_t, out_v = 0, [], []
    for t, v in zip(times.tolist(), x.tolist(), strict=True):
        if np.isfinite(v):
            p.set_inputs([0], [v])
        if t >= next_step:
            p.step((t - int(times[0])) / 1e9)
            next_step = t + round(spacing_s * 1e9)
        got = p.get_outputs(refs)
        if got is not None:
            out_v.append([float(g) for g in got])
            out_t.append(int(times[0]) + round(p.get_time() * 1e9))
    return out_t, out_v


def run(bp: Any, times: np.ndarray, x: np.ndarray, cuts: list[int]) -> Batch:
    bp.start()
    outs = [bp.process(Batch.of(times[a:b], measurement=x[a:b])) for a, b in pairwise(cuts)]
    return Batch.concat([o for o in outs if o is not None])


def test_the_blueprint_class_and_its_params() -> None:
    assert SMOOTHING.name == "tvilling_style" and SMOOTHING.keeps_state is False
    info = describe_blueprint(SMOOTHING)
    assert info["title"] == "Exponential smoothing"
    props = info["params_schema"]["properties"]
    assert props["time_constant"]["type"] == "number" and props["time_constant"]["default"] == 0.5
    assert props["time_constant"]["description"] == "the time constant of the filter in seconds"
    assert props["warmup"]["type"] == "integer"  # from the annotation
    assert {s["type"] for s in props["gain"]["anyOf"]} == {"integer", "number"}
    assert props["mode"]["type"] == "string" and props["mode"]["default"] == "ema"
    assert {"start_params", "outputs"} <= set(props)
    assert "required" not in info["params_schema"]
    with pytest.raises(ValidationError, match="time_constant"):
        SMOOTHING.Params(time_constant="slow")
    with pytest.raises(ValidationError, match="extra"):
        SMOOTHING.Params(time_constnat=1.0)


@pytest.mark.parametrize("spacing", [0.0, 0.035])
def test_matches_the_original_loop_for_any_split(tmp_path: Path, spacing: float) -> None:
    rng = np.random.default_rng(1)
    n = 400
    times = T0 + np.cumsum(rng.integers(5, 15, n)) * MS
    x = np.sin(np.arange(n) / 20) + rng.normal(0, 0.1, n)
    x[rng.random(n) < 0.1] = np.nan
    kwargs: dict[str, Any] = {"time_constant": 0.2, "gain": 2, "warmup": 3}
    want_t, want_v = by_hand(times, x, spacing, [0, 1, 2], **kwargs)
    p = SMOOTHING.Params(**kwargs)
    bp = SMOOTHING(p, ctx(tmp_path, spacing))
    assert bp.inputs() == ["measurement"] and bp.outputs() == ["smoothed", "rate", "steps"]
    whole = run(bp, times, x, [0, n])
    cuts = [0, 1, *sorted(rng.choice(np.arange(2, n), 20, replace=False).tolist()), n]
    split = run(SMOOTHING(p, ctx(tmp_path, spacing)), times, x, cuts)
    for got in (whole, split):
        assert got.times.tolist() == want_t
        np.testing.assert_array_equal(
            np.column_stack([got["smoothed"], got["rate"], got["steps"]]), want_v
        )
    if spacing:
        assert whole["steps"][-1] < n / 2  # steps were skipped: outputs repeat the last step


def test_chosen_outputs_and_start_params(tmp_path: Path) -> None:
    times = T0 + np.arange(50) * 10 * MS
    x = np.linspace(0, 1, 50)
    p = SMOOTHING.Params(outputs=["steps", "smoothed"], start_params={"initial": 5.0})
    bp = SMOOTHING(p, ctx(tmp_path))
    assert bp.outputs() == ["steps", "smoothed"]
    assert bp.describe()["outputs"] == [
        {"name": "steps", "valueReference": 2},
        {"name": "smoothed", "valueReference": 0},
    ]
    assert [o["name"] for o in bp.describe()["available_outputs"]] == ["smoothed", "rate", "steps"]
    got = run(bp, times, x, [0, 20, 50])
    want_t, want_v = by_hand(times, x, 0.0, [2, 0], start_params={"initial": 5.0})
    assert got.times.tolist() == want_t
    np.testing.assert_array_equal(np.column_stack([got["steps"], got["smoothed"]]), want_v)
    assert want_v[0][1] == pytest.approx(5.0)  # started from the start parameter


def test_a_missing_input_skips_set_inputs_only(tmp_path: Path) -> None:
    bp = SMOOTHING(SMOOTHING.Params(mode="hold"), ctx(tmp_path))
    bp.start()
    out = bp.process(Batch.of(T0 + np.arange(3) * MS, measurement=[1.0, np.nan, 3.0]))
    assert out is not None and out["smoothed"].tolist() == [1.0, 1.0, 3.0]
    out = bp.process(Batch.of([T0 + 5 * MS], other=[9.0]))  # no measurement column at all
    assert out is not None and out["smoothed"].tolist() == [3.0] and out["steps"].tolist() == [4]
    assert bp.process(Batch.empty(["measurement"])) is None


def test_variables_with_value_references_and_no_inputs(tmp_path: Path) -> None:
    assert RAMP.name == "ramp" and (RAMP.__doc__ or "").startswith("Ramp")
    p = RAMP.Params(start_value=1.0, ramp_delay=0.5, start_params={"slope": 2.0})
    bp = RAMP(p, ctx(tmp_path))
    assert bp.inputs() == [] and bp.outputs() == ["ramp", "seconds"]
    bp.start()
    out = bp.process(Batch.of(T0 + np.arange(0, 1001, 250) * MS, anything=np.zeros(5)))
    assert out is not None
    assert out["seconds"].tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert out["ramp"].tolist() == [1.0, 1.0, 1.0, 1.5, 2.0]
    only = RAMP(RAMP.Params(outputs=["seconds"]), ctx(tmp_path))
    only.start()
    got = only.process(Batch.of([T0, T0 + 10**9]))
    assert got is not None and list(got.columns) == ["seconds"]
    with pytest.raises(BlueprintError, match="stop: the ramp was stopped"):
        bp.stop()


def test_errors_of_p_become_blueprint_errors(tmp_path: Path) -> None:
    with pytest.raises(BlueprintError, match="time_constant must be positive"):
        SMOOTHING(SMOOTHING.Params(time_constant=0), ctx(tmp_path))
    bp = SMOOTHING(SMOOTHING.Params(limit=1.0), ctx(tmp_path))
    bp.start()
    with pytest.raises(BlueprintError, match=r"set_inputs: measurement 5.0 is beyond 1.0"):
        bp.process(Batch.of([T0], measurement=[5.0]))
    with pytest.raises(BlueprintError, match="no output 'speed'"):
        SMOOTHING(SMOOTHING.Params(outputs=["speed"]), ctx(tmp_path))
    with pytest.raises(ValidationError, match="input_proportions"):
        SMOOTHING.Params(input_proportions={"x": 2})  # the runtime's input scale does that


class Odd:
    """Odd one: a P with awkward parameter names and bad outputs."""

    input_names = ("a",)
    output_names = ("b", "c")

    def __init__(self, json="j", _private=1, count=None, *args: Any, **kwargs: Any) -> None:
        self.json, self.private, self.count = json, _private, count

    def set_inputs(self, refs: list[int], values: list[float]) -> None:
        self.value = values[0]

    def step(self, t: float) -> None:
        pass

    def get_outputs(self, refs: list[int]) -> Any:
        return {1.0: [1.0], 2.0: ["x", "y"]}.get(self.value, [self.json, self.private])


def test_awkward_parameter_names_and_bad_outputs(tmp_path: Path) -> None:
    cls = tvilling_blueprint("odd", Odd)
    props = cls.Params.model_json_schema()["properties"]
    assert {"json", "_private", "count"} <= set(props)
    bp = cls(cls.Params(json="4", _private=5), ctx(tmp_path))
    bp.start()
    out = bp.process(Batch.of([T0], a=[0.0]))
    assert out is not None and out["b"].tolist() == [4.0] and out["c"].tolist() == [5.0]
    with pytest.raises(BlueprintError, match="1 values for 2 outputs"):
        bp.process(Batch.of([T0 + 1], a=[1.0]))
    with pytest.raises(BlueprintError, match="not numbers"):
        bp.process(Batch.of([T0 + 2], a=[2.0]))


def test_a_parameter_named_like_the_adapters_own_is_refused() -> None:
    class Clash:
        def __init__(self, outputs=1) -> None:
            pass

    with pytest.raises(BlueprintError, match="'outputs' clashes"):
        tvilling_blueprint("clash", Clash)


def test_loading_something_that_is_not_a_blueprint(tmp_path: Path) -> None:
    (tmp_path / "empty.py").write_text("X = 1\n")
    (tmp_path / "broken.py").write_text("import nothing_of_that_name\n")
    with pytest.raises(BlueprintError, match="defines no class P"):
        load_tvilling(tmp_path / "empty.py")
    with pytest.raises(BlueprintError, match="cannot be imported"):
        load_tvilling(tmp_path / "broken.py")
    with pytest.raises(BlueprintError, match="not a Python module"):
        load_tvilling(tmp_path / "missing.py")
