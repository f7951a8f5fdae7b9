"""The expression blueprint: results against numpy written by hand, and every way out of the
language refused with a message naming the offending part and its column."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from twinlink.processors.blueprint import Batch, BlueprintError, Context
from twinlink.processors.blueprints.expression import (
    FUNCTIONS,
    Expression,
    ExpressionParams,
    check_expression,
    compile_expression,
)

T0 = 1_700_000_000_000_000_000
RNG = np.random.default_rng(0)
X = RNG.uniform(-2, 2, 50)
Y = RNG.uniform(0.1, 3, 50)
Z = RNG.uniform(-1, 1, 50)


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def evaluate(text: str, **env: np.ndarray) -> np.ndarray:
    fn, _ = compile_expression(text)
    with np.errstate(all="ignore"):
        return np.broadcast_to(fn(env), (len(next(iter(env.values()))),))


CASES = [
    ("x + y - z * 2", X + Y - Z * 2),
    ("x / y", X / Y),
    ("x // y", X // Y),
    ("x % y", X % Y),
    ("y ** 2.5", Y**2.5),
    ("2 ** -x", 2.0**-X),
    ("-x + +y", -X + Y),
    ("x > 0.5", (X > 0.5).astype(float)),
    ("z <= x < y", ((Z <= X) & (X < Y)).astype(float)),
    ("x == x and y != 1", np.ones(50)),
    ("x > 0 or z > 0", ((X > 0) | (Z > 0)).astype(float)),
    ("not x > 0", (X <= 0).astype(float)),
    ("x if z > 0 else y", np.where(Z > 0, X, Y)),
    ("where(x > 0.5, 1, 0)", np.where(X > 0.5, 1.0, 0.0)),
    ("sqrt(x**2 + y**2)", np.sqrt(X**2 + Y**2)),
    ("hypot(x, y)", np.hypot(X, Y)),
    ("atan2(y, x)", np.arctan2(Y, X)),
    ("min(x, y, z)", np.minimum(np.minimum(X, Y), Z)),
    ("max(x, 0)", np.maximum(X, 0)),
    ("clip(x, -1, 1)", np.clip(X, -1, 1)),
    ("asin(z) + acos(z) + atan(x)", np.arcsin(Z) + np.arccos(Z) + np.arctan(X)),
    (
        "round(x * 10) + floor(x) + ceil(y) + sign(x)",
        np.rint(X * 10) + np.floor(X) + np.ceil(Y) + np.sign(X),
    ),
    ("degrees(pi) + radians(180) + e", np.full(50, 180 + np.pi + np.e)),
    ("log(y) + log10(y) + exp(z) + abs(x)", np.log(Y) + np.log10(Y) + np.exp(Z) + np.abs(X)),
    ("sin(x) * cos(y) / tan(z + 3)", np.sin(X) * np.cos(Y) / np.tan(Z + 3)),
    ("sinh(z) + cosh(z) + tanh(x)", np.sinh(Z) + np.cosh(Z) + np.tanh(X)),
    ("isnan(x / 0 * 0)", np.ones(50)),
    ("force * 0.3 / 2.1e-12 * 5e-4", X * 0.3 / 2.1e-12 * 5e-4),
]


@pytest.mark.parametrize(("text", "want"), CASES, ids=[c[0] for c in CASES])
def test_evaluates_like_numpy(text: str, want: np.ndarray) -> None:
    got = evaluate(text, x=X, y=Y, z=Z, force=X)
    np.testing.assert_allclose(got, want, rtol=1e-12)
    assert got.dtype == np.float64


def test_every_function_of_the_table_is_covered() -> None:
    used = {name for text, _ in CASES for name in FUNCTIONS if f"{name}(" in text}
    assert used == set(FUNCTIONS)


def test_free_names_in_order_of_first_use() -> None:
    assert check_expression("sqrt(ax**2 + ay**2) + ax * pi") == ["ax", "ay"]
    assert check_expression("1 + 2") == []
    assert check_expression("where(angle > 0.5, 1, nan)") == ["angle"]


def test_division_by_zero_and_huge_powers_neither_raise_nor_hang() -> None:
    ones = np.ones(3)
    assert np.isposinf(evaluate("x / 0", x=ones)).all()
    assert np.isnan(evaluate("0 / 0 + x", x=ones)).all()
    assert np.isnan(evaluate("x % 0", x=ones)).all()
    start = time.perf_counter()
    assert np.isposinf(evaluate("10**10**10 + x", x=ones)).all()
    assert np.isposinf(evaluate("(x + 9) ** 10**10", x=ones)).all()
    assert np.isposinf(evaluate("99999999999999999999 ** 99999999999999999999 * x", x=ones)).all()
    assert time.perf_counter() - start < 0.5


ESCAPES = [
    ("__import__('os')", "'__import__' at column 0", "only these functions"),
    ("().__class__", "'().__class__' at column 0", "attribute access"),
    ("x.__class__", "'x.__class__' at column 0", "attribute access"),
    ("open('f')", "'open' at column 0", "only these functions"),
    ("[1]", "'[1]' at column 0", "list"),
    ("lambda: 1", "'lambda: 1' at column 0", "lambda"),
    ('"s"', "'\"s\"' at column 0", "a string"),
    ("1 + b'x'", "\"b'x'\" at column 4", "a string"),
    ("x + y[0]", "'y[0]' at column 4", "subscripting"),
    ("sqrt(x, y)", "'sqrt(x, y)' at column 0", "takes 1 argument"),
    ("where(x, 1, y=2)", "'y=2' at column 12", "keyword arguments"),
    ("np.sin(x)", "'np.sin' at column 0", "only these functions"),
    ("sqrt", "'sqrt' at column 0", "must be called"),
    ("x + __builtins__", "'__builtins__' at column 4", "double underscores"),
    ("[c for c in x]", "at column 0", "comprehension"),
    ("(y := 2)", "at column 1", "assignment"),
    ("f'{x}'", "at column 0", "a string"),
    ("x & 1", "'x & 1' at column 0", "bitwise"),
    ("x in y", "'x in y' at column 0", "comparison 'in'"),
    ("~x", "'~x' at column 0", "bitwise inversion"),
    ("x is not y", "at column 0", "comparison 'is not'"),
    ("max(x)", "'max(x)' at column 0", "takes 2 to 32 arguments"),
    ("True + x", "'True' at column 0", "only numbers"),
    ("1j * x", "'1j' at column 0", "only numbers"),
    ("{1: 2}", "at column 0", "dict"),
    ("x if y", "syntax error at column", ""),
    ("", "syntax error", ""),
    ("x; import os", "syntax error", ""),
    ("-" * 150 + "x", "nested more than 100 deep", ""),
    ("sqrt(" * 150 + "x" + ")" * 150, "nested more than 100 deep", ""),
    ("-" * 9000 + "x", "nested more than 100 deep", ""),
    ("(" * 300 + "x" + ")" * 300, "syntax error", "too many nested parentheses"),
    ("x+" * 6000 + "x", "longer than 10000 characters", ""),
]


@pytest.mark.parametrize(("text", "where", "why"), ESCAPES, ids=[e[0][:30] for e in ESCAPES])
def test_anything_outside_the_language_is_refused(text: str, where: str, why: str) -> None:
    with pytest.raises(BlueprintError) as e:
        check_expression(text)
    assert where in str(e.value) and why in str(e.value)


def test_the_blueprint_reads_the_names_it_uses(tmp_path: Path) -> None:
    p = ExpressionParams(
        outputs={"speed": "sqrt(ax**2 + ay**2)", "alarm": "where(angle > 0.5, 1, 0)", "k": "2"}
    )
    bp = Expression(p, ctx(tmp_path))
    assert bp.inputs() == ["ax", "ay", "angle"]
    assert bp.outputs() == ["speed", "alarm", "k"]
    times = T0 + np.arange(4)
    batch = Batch.of(times, ax=[3.0, 1.0, np.nan, 0.0], ay=[4.0, 1.0, 1.0, 0.0])
    out = bp.process(batch)  # angle is absent: NaN, and NaN > 0.5 is 0
    assert out is not None
    np.testing.assert_array_equal(out.times, times)
    np.testing.assert_allclose(out["speed"], [5.0, np.sqrt(2), np.nan, 0.0])
    np.testing.assert_array_equal(out["alarm"], [0.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(out["k"], [2.0, 2.0, 2.0, 2.0])


def test_rows_where_every_output_is_missing_are_left_out(tmp_path: Path) -> None:
    bp = Expression(ExpressionParams(outputs={"y": "x * 2", "z": "x + w"}), ctx(tmp_path))
    out = bp.process(Batch.of(T0 + np.arange(4), x=[1.0, np.nan, 3.0, np.nan], w=[1, 1, 1, 1]))
    assert out is not None
    assert out.times.tolist() == [T0, T0 + 2] and out["z"].tolist() == [2.0, 4.0]
    assert bp.process(Batch.of([T0 + 9], other=[1.0])) is None
    assert bp.process(Batch.empty(["x"])) is None


def test_declared_signals_catch_a_misspelt_name(tmp_path: Path) -> None:
    p = ExpressionParams(outputs={"y": "x + 1", "z": "x + wx"}, signals=["x", "w"])
    with pytest.raises(BlueprintError, match=r"output 'z': 'wx' at column 4: unknown signal"):
        Expression(p, ctx(tmp_path))
    ok = ExpressionParams(outputs={"y": "x + w"}, signals=["x", "w"])
    assert Expression(ok, ctx(tmp_path)).inputs() == ["x", "w"]


def test_reconfigure_recompiles_in_place(tmp_path: Path) -> None:
    bp = Expression(ExpressionParams(outputs={"y": "x * 2"}), ctx(tmp_path))
    assert bp.reconfigure(ExpressionParams(outputs={"y": "x * 3", "v": "u"})) is True
    assert bp.inputs() == ["x", "u"]
    out = bp.process(Batch.of([T0], x=[2.0], u=[5.0]))
    assert out is not None and out["y"].tolist() == [6.0] and out["v"].tolist() == [5.0]
    with pytest.raises(BlueprintError, match="attribute access"):
        bp.reconfigure(ExpressionParams(outputs={"y": "x.real"}))


def test_bad_params() -> None:
    with pytest.raises(ValidationError, match="outputs"):
        ExpressionParams(outputs={})
    with pytest.raises(ValidationError, match="extra"):
        ExpressionParams(outputs={"y": "x"}, inputs=["x"])


def test_throughput_is_vectorised(tmp_path: Path) -> None:
    n = 1_000_000
    bp = Expression(ExpressionParams(outputs={"s": "sqrt(ax**2 + ay**2) * 0.5"}), ctx(tmp_path))
    batch = Batch.of(np.arange(n) + T0, ax=np.ones(n), ay=np.ones(n))
    start = time.perf_counter()
    out = bp.process(batch)
    assert out is not None and len(out) == n
    assert time.perf_counter() - start < 1.0  # about 0.02 s: far above 100 000 samples/s
