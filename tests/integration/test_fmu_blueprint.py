"""The fmu blueprint on small C FMUs (a first-order lag, see _fmu_c.py)."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from tests.integration._fmu_c import build_fmu
from twinlink.processors.blueprint import Batch, BlueprintError, Context
from twinlink.processors.blueprints.fmu import FmuBlueprint, FmuParams

pytestmark = pytest.mark.integration

S = 1_000_000_000
T0 = 1_700_000_000 * S
Make = Callable[..., FmuBlueprint]


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("fmus")
    build_fmu(folder, 2, "lag2.fmu")
    build_fmu(folder, 3, "lag3.fmu")
    return folder


@pytest.fixture
def blueprint(files: Path, tmp_path: Path) -> Callable[..., FmuBlueprint]:
    count = iter(range(1000))

    def blueprint(**params: Any) -> FmuBlueprint:
        workdir = tmp_path / f"work{next(count)}"
        workdir.mkdir()
        ctx = Context(processor="p", twin="t", files=files, workdir=workdir)
        return FmuBlueprint(FmuParams(**{"fmu": "lag2.fmu", **params}), ctx)

    return blueprint


@pytest.fixture
def make(blueprint: Callable[..., FmuBlueprint]) -> Iterator[Make]:
    started: list[FmuBlueprint] = []

    def make(**params: Any) -> FmuBlueprint:
        bp = blueprint(**params)
        bp.start()
        started.append(bp)
        return bp

    yield make
    for bp in started:
        bp.stop()


def lag(t: np.ndarray, u: np.ndarray, y0: float = 0.0, tau: float = 1.0) -> np.ndarray:
    """The exact samples-mode answer: each sample's input over the interval before it."""
    y = np.empty(len(t))
    y[0] = y0
    for k in range(1, len(t)):
        y[k] = u[k] + (y[k - 1] - u[k]) * math.exp(-(t[k] - t[k - 1]) / tau)
    return y


def run(bp: FmuBlueprint, t_s: np.ndarray, **columns: Any) -> Batch:
    out = bp.process(Batch.of(T0 + np.rint(np.asarray(t_s) * S).astype(np.int64), **columns))
    assert out is not None
    return out


@pytest.mark.parametrize("fmu", ["lag2.fmu", "lag3.fmu"])
def test_samples_mode_is_the_exact_lag(make: Make, fmu: str) -> None:
    bp = make(fmu=fmu)
    assert (bp.inputs(), bp.outputs()) == (["u"], ["y", "g", "n"])
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.integers(1, 200_000_000, 200)) * 1e-9  # whole nanoseconds
    t -= t[0]
    u = rng.uniform(-5, 5, 200)
    half = 100
    first, second = run(bp, t[:half], u=u[:half]), run(bp, t[half:], u=u[half:])
    y = np.concatenate([first["y"], second["y"]])
    np.testing.assert_allclose(y, lag(t, u), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(first["g"], 2 * u[:half])
    assert first.times[0] == T0 and list(first.columns) == ["y", "g", "n"]
    assert first["n"].dtype == np.float64


def test_repeated_and_earlier_samples_do_not_step(make: Make) -> None:
    bp = make()
    out = run(bp, np.array([0.0, 1.0, 1.0, 0.5]), u=[1.0, 1.0, 3.0, 4.0])
    y1 = 1 - math.exp(-1)
    np.testing.assert_allclose(out["y"], [0, y1, y1, y1])
    np.testing.assert_array_equal(out["g"], [2, 2, 6, 8])


def test_fixed_mode_steps_on_the_grid_with_held_inputs(make: Make) -> None:
    bp = make(step="fixed", step_size_s=0.1)
    out = run(bp, np.array([0.0, 0.25, 0.5]), u=[1.0, 2.0, 3.0])
    np.testing.assert_array_equal(out.times, T0 + np.arange(1, 6) * S // 10)
    held = np.array([1, 1, 2, 2, 2])  # a sample's input applies from its time on
    np.testing.assert_array_equal(out["g"], 2 * held)
    y, expected = 0.0, []
    for u in held:
        y = u + (y - u) * math.exp(-0.1)
        expected.append(y)
    np.testing.assert_allclose(out["y"], expected, atol=1e-12)
    assert bp.process(Batch.of([T0 + 55 * S // 100], u=[0.0])) is None  # no step fits yet
    later = run(bp, np.array([1.0]), u=[4.0])
    np.testing.assert_array_equal(later.times, T0 + np.arange(6, 11) * S // 10)
    np.testing.assert_array_equal(later["g"], [0, 0, 0, 0, 0])  # u = 0 from 0.55 s on


def test_clamped_inputs_are_counted_and_evented_once_per_second(make: Make) -> None:
    bp = make()
    t = np.arange(26) * 0.1
    first = run(bp, t[:13], u=np.full(13, 20.0))
    second = run(bp, t[13:], u=np.full(13, 20.0))
    np.testing.assert_array_equal(np.concatenate([first["g"], second["g"]]), 20.0)
    events = bp.ctx.events
    assert [e.kind for e in events] == ["input_clamped"] * 3
    assert [e.time_ns for e in events] == [T0, T0 + S, T0 + 2 * S]
    assert [e.data["count"] for e in events] == [1, 11, 21]
    assert events[0].data == {"input": "u", "value": 20.0, "count": 1, "min": -10.0, "max": 10.0}
    assert bp.describe()["state"]["clamped"] == {"u": 26}


def test_rejected_inputs_skip_the_sample(make: Make) -> None:
    bp = make(out_of_range="reject")
    out = run(bp, np.arange(5.0), u=[1.0, 20.0, 2.0, -30.0, 3.0])
    np.testing.assert_array_equal(out.times, T0 + np.array([0, 2, 4]) * S)
    np.testing.assert_array_equal(out["g"], [2, 4, 6])
    assert [(e.kind, e.time_ns, e.data["count"]) for e in bp.ctx.events] == [
        ("input_rejected", T0 + S, 1),
        ("input_rejected", T0 + 3 * S, 2),
    ]
    state = bp.describe()["state"]
    assert state["rejected"] == {"u": 2} and state["skipped_samples"] == 2


def test_missing_values_hold_the_previous_one(make: Make) -> None:
    bp = make(parameters={"u": 3})
    out = bp.process(Batch.of([T0, T0 + S], v=[0.0, 0.0]))  # no u column at all
    assert out is not None
    np.testing.assert_array_equal(out["g"], [6, 6])  # the start value set by parameters
    out = run(bp, np.array([2.0, 3.0, 4.0, 5.0]), u=[1.0, np.nan, np.nan, 2.0])
    np.testing.assert_array_equal(out["g"], [2, 2, 2, 4])


def test_parameters_and_start_values_by_name(make: Make) -> None:
    bp = make(parameters={"tau": 2, "y": 0.5})
    t, u = np.arange(0, 3, 0.1), np.ones(30)
    np.testing.assert_allclose(run(bp, t, u=u)["y"], lag(t, u, y0=0.5, tau=2.0), atol=1e-12)


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"parameters": {"nope": 1, "tau": 2}}, r"unknown FMU parameters: nope \(valid: u, y, "),
        ({"parameters": {"g": 1.0}}, r"cannot be set: g \(output, continuous\)"),
        ({"parameters": {"tau": "slow"}}, "tau .Real. cannot take 'slow'"),
        ({"inputs": ["x"]}, "unknown FMU inputs: x"),
        ({"inputs": ["y"]}, r"not scalar inputs of a number type: y \(output Real\)"),
        ({"outputs": ["y", "label"]}, r"only numeric scalar variables can be outputs: label"),
        ({"fmu": "none.fmu"}, "no FMU file none.fmu"),
        ({"parameters": {"tau": -1.0}}, r"tau = -1.0 is outside its range \[1e-06, \]"),
        ({"parameters": {"u": 10.5}}, r"u = 10.5 is outside its range \[-10, 10\]"),
        ({"parameters": {"tau": 2e6}}, r"fmi2SetReal returned error: .*tau must be in \(0, 1e6\]"),
    ],
)
def test_start_refuses(blueprint: Callable[..., FmuBlueprint], params: Any, message: str) -> None:
    bp = blueprint(**params)
    with pytest.raises(BlueprintError, match=message):
        bp.start()
    bp.stop()


def test_params_validation() -> None:
    for name in ("../lag2.fmu", "a/lag2.fmu", "a\\lag2.fmu", "..", ""):
        with pytest.raises(ValidationError, match="plain file name"):
            FmuParams(fmu=name)
    with pytest.raises(ValidationError, match="needs step_size_s"):
        FmuParams(fmu="x.fmu", step="fixed")
    with pytest.raises(ValidationError):
        FmuParams(fmu="x.fmu", step="fixed", step_size_s=0)
    with pytest.raises(ValidationError):
        FmuParams.model_validate({"fmu": "x.fmu", "typo": 1})


@pytest.mark.parametrize("fmu", ["lag2.fmu", "lag3.fmu"])
@pytest.mark.parametrize(("solver", "atol"), [("CVode", 2e-4), ("Euler", 5e-4)])
def test_model_exchange(make: Make, fmu: str, solver: str, atol: float) -> None:
    bp = make(fmu=fmu, fmi_type="ModelExchange", solver=solver, solver_step_s=1e-3)
    t = np.arange(0, 1.5, 0.01)
    out = run(bp, t, u=np.ones(len(t)))
    error = np.abs(out["y"] - (1 - np.exp(-t)))
    assert error.max() < atol
    assert solver == "CVode" or error.max() > 1e-5  # Euler really is Euler
    np.testing.assert_array_equal(out["n"], t > math.log(2))  # the state event y = 0.5
    assert bp.describe()["mode"] == {
        "fmi_type": "ModelExchange",
        "step": "samples",
        "step_size_s": None,
        "out_of_range": "clamp",
        "solver": solver,
        "solver_step_s": 1e-3,
    }


def test_model_exchange_with_changing_inputs(make: Make) -> None:
    bp = make(fmi_type="ModelExchange")
    t = np.arange(0, 2, 0.05)
    u = np.where(t < 1, 2.0, -1.0)
    np.testing.assert_allclose(run(bp, t, u=u)["y"], lag(t, u), atol=2e-4)


@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_reconfigure_tunable_parameter_keeps_state(make: Make, kind: str) -> None:
    bp = make(fmi_type=kind)
    t, u = np.arange(0, 2, 0.1), np.ones(20)
    first = run(bp, t[:10], u=u[:10])
    assert bp.reconfigure(FmuParams(fmu="lag2.fmu", fmi_type=kind, parameters={"tau": 2.0}))
    second = run(bp, t[10:], u=u[10:])
    y = np.concatenate([first["y"], second["y"]])
    expected = lag(t[:10], u[:10])
    expected = np.concatenate([expected, lag(t[9:], u[9:], y0=expected[-1], tau=2.0)[1:]])
    np.testing.assert_allclose(y, expected, atol=1e-12 if kind == "CoSimulation" else 2e-4)
    assert bp.params.parameters == {"tau": 2.0}


def test_reconfigure_what_needs_a_restart(make: Make) -> None:
    bp = make(parameters={"tau": 2.0, "y": 0.1})
    base = {"fmu": "lag2.fmu", "parameters": {"tau": 2.0, "y": 0.1}}
    assert not bp.reconfigure(FmuParams(**{**base, "step": "fixed", "step_size_s": 0.1}))
    assert not bp.reconfigure(FmuParams(**{**base, "parameters": {"tau": 2.0}}))  # removed
    assert not bp.reconfigure(FmuParams(**{**base, "parameters": {"tau": 2.0, "y": 0.2}}))
    assert not bp.reconfigure(FmuParams(**{**base, "parameters": {"tau": -1.0, "y": 0.1}}))
    assert bp.reconfigure(FmuParams(**{**base, "out_of_range": "reject"}))
    out = run(bp, np.arange(3.0), u=[1.0, 11.0, 1.0])
    assert len(out) == 2 and bp.params.out_of_range == "reject"
    assert not bp.reconfigure(FmuParams(**{**base, "parameters": {"tau": 2e6, "y": 0.1}}))
    with pytest.raises(BlueprintError, match=r"tau must be in .* it must be restarted"):
        run(bp, np.arange(3.0, 4.0), u=[1.0])  # the FMU refused the value: restart
    assert not bp.reconfigure(FmuParams(**base))


@pytest.mark.parametrize(("fmu", "function"), [("lag2.fmu", "fmi2"), ("lag3.fmu", "fmi3")])
def test_do_step_error_carries_the_fmu_log(make: Make, fmu: str, function: str) -> None:
    bp = make(fmu=fmu)
    run(bp, np.arange(2.0), u=[1.0, 2.0])
    with pytest.raises(BlueprintError) as err:
        run(bp, np.array([2.0, 3.0]), u=[-7.0, 1.0])
    assert str(err.value) == (
        f"{function}DoStep returned error at t = 1 s: [error] logStatusError: u = -7 is not allowed"
    )
    with pytest.raises(BlueprintError, match=r"the FMU failed .* restarted"):
        run(bp, np.array([4.0]), u=[1.0])
    bp.stop()  # does not raise, does not call terminate on the failed instance
    bp.stop()


def test_fixed_integer_outputs_and_describe(make: Make) -> None:
    bp = make(fmu="lag3.fmu", outputs=["n", "y"], step="fixed", step_size_s=0.5)
    out = run(bp, np.array([0.0, 3.0]), u=[1.0, 1.0])
    assert list(out.columns) == ["n", "y"]
    np.testing.assert_array_equal(out["n"], [0, 1, 1, 1, 1, 1])
    d = bp.describe()
    assert d["fmi_version"] == "3.0" and d["inputs"] == ["u"] and d["outputs"] == ["n", "y"]
    assert d["mode"]["step"] == "fixed" and d["state"]["time_s"] == 3.0
    assert {v["name"] for v in d["variables"]} >= {"u", "y", "tau"}
