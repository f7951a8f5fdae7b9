"""Derived signals from a small, safe expression language evaluated on numpy arrays.

Parsed with `ast` (mode "eval"); only numbers, names, arithmetic, comparisons, and/or/not,
`a if c else b` and calls of `FUNCTIONS` are accepted, compiled into closures over numpy
arrays (the text never reaches eval or exec). All arithmetic is on float64, so `10**10**10`
is inf at once, and floating-point errors are ignored: x / 0 is inf or nan, not an exception.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping
from functools import reduce
from itertools import pairwise
from typing import Any

import numpy as np
import numpy.typing as npt
from pydantic import Field

from twinlink.processors.blueprint import Batch, Blueprint, BlueprintError, Context, Params

Array = npt.NDArray[np.float64]
Env = Mapping[str, Array]
Fn = Callable[[Env], Array]

MAX_DEPTH = 100
MAX_LENGTH = 10_000
CONSTANTS = {"pi": np.pi, "e": np.e, "nan": np.nan, "inf": np.inf}


def _where(c: Array, a: Array, b: Array) -> Array:
    return np.where(c != 0, a, b)


def _fold(ufunc: np.ufunc) -> Callable[..., Array]:
    return lambda *args: reduce(ufunc, args)


_SAME_NAME = "abs sqrt exp log log10 sin cos tan sinh cosh tanh floor ceil sign degrees radians"
_RENAMED = {"asin": np.arcsin, "acos": np.arccos, "atan": np.arctan, "round": np.rint}
# name: (function, least and most arguments)
FUNCTIONS: dict[str, tuple[Callable[..., Any], int, int]] = {
    **{name: (getattr(np, name), 1, 1) for name in [*_SAME_NAME.split(), "isnan"]},
    **{name: (fn, 1, 1) for name, fn in _RENAMED.items()},
    "atan2": (np.arctan2, 2, 2),
    "hypot": (np.hypot, 2, 2),
    "clip": (np.clip, 3, 3),
    "min": (_fold(np.minimum), 2, 32),
    "max": (_fold(np.maximum), 2, 32),
    "where": (_where, 3, 3),
}
_ARITHMETIC = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply}
_DIVISION = {ast.Div: np.true_divide, ast.FloorDiv: np.floor_divide, ast.Mod: np.mod}
BINARY: dict[type[ast.operator], np.ufunc] = {**_ARITHMETIC, **_DIVISION, ast.Pow: np.power}
_ORDER = {ast.Lt: np.less, ast.LtE: np.less_equal, ast.Gt: np.greater}
_EQUALITY = {ast.GtE: np.greater_equal, ast.Eq: np.equal, ast.NotEq: np.not_equal}
COMPARE: dict[type[ast.cmpop], np.ufunc] = {**_ORDER, **_EQUALITY}


def _float(x: Any) -> Array:
    return np.asarray(x, dtype=np.float64)


class _Compiler:
    """Turns one expression into a closure, collecting the signal names it reads."""

    def __init__(self, text: str, signals: set[str] | None) -> None:
        self.text = text
        self.signals = signals
        self.names: dict[str, None] = {}

    def fail(self, node: ast.AST, why: str) -> BlueprintError:
        part = ast.get_source_segment(self.text, node) or type(node).__name__
        if len(part) > 40:
            part = part[:37] + "..."
        col = getattr(node, "col_offset", 0)
        return BlueprintError(f"{part!r} at column {col}: {why}")

    def compile(self, node: ast.AST, depth: int = 0) -> Fn:
        if depth > MAX_DEPTH:
            raise self.fail(node, f"the expression is nested more than {MAX_DEPTH} deep")
        kinds: dict[type[ast.AST], Callable[[Any, int], Fn]] = {
            ast.Constant: self.constant,
            ast.Name: self.name,
            ast.BinOp: self.binary,
            ast.UnaryOp: self.unary,
            ast.Compare: self.comparison,
            ast.BoolOp: self.boolean,
            ast.IfExp: self.conditional,
            ast.Call: self.function,
        }
        if type(node) not in kinds:
            raise self.fail(node, f"{describe(node)} is not allowed in an expression")
        return kinds[type(node)](node, depth)

    def constant(self, node: ast.Constant, depth: int) -> Fn:
        value = node.value
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(node, f"{describe(node)} is not allowed: only numbers are")
        try:
            number = _float(float(value))
        except OverflowError as err:
            raise self.fail(node, "the number is too large") from err
        return lambda env: number

    def name(self, node: ast.Name, depth: int) -> Fn:
        name = node.id
        if "__" in name:
            raise self.fail(node, "names with double underscores are not allowed")
        if name in FUNCTIONS:
            raise self.fail(node, f"the function {name!r} must be called: {name}(...)")
        if name in CONSTANTS:
            number = _float(CONSTANTS[name])
            return lambda env: number
        if self.signals is not None and name not in self.signals:
            raise self.fail(node, f"unknown signal {name!r}: not among the declared signals")
        self.names[name] = None
        return lambda env: env[name]

    def binary(self, node: ast.BinOp, depth: int) -> Fn:
        if type(node.op) not in BINARY:
            raise self.fail(node, "bitwise and matrix operators (& | ^ << >> @) are not allowed")
        return self.call(BINARY[type(node.op)], [node.left, node.right], depth)

    def conditional(self, node: ast.IfExp, depth: int) -> Fn:
        return self.call(_where, [node.test, node.body, node.orelse], depth)

    def unary(self, node: ast.UnaryOp, depth: int) -> Fn:
        f = self.compile(node.operand, depth + 1)
        if isinstance(node.op, ast.USub):
            return lambda env: _float(np.negative(f(env)))
        if isinstance(node.op, ast.UAdd):
            return f
        if isinstance(node.op, ast.Not):
            return lambda env: _float(f(env) == 0)
        raise self.fail(node, "bitwise inversion (~) is not allowed")

    def comparison(self, node: ast.Compare, depth: int) -> Fn:
        for op in node.ops:
            if type(op) not in COMPARE:
                word = {ast.In: "in", ast.NotIn: "not in", ast.Is: "is"}.get(type(op), "is not")
                raise self.fail(node, f"the comparison {word!r} is not allowed")
        ops = [COMPARE[type(op)] for op in node.ops]
        parts = [self.compile(n, depth + 1) for n in [node.left, *node.comparators]]

        def compare(env: Env) -> Array:
            v = [p(env) for p in parts]
            pairs = [op(a, b) for op, (a, b) in zip(ops, pairwise(v), strict=True)]
            return _float(reduce(np.logical_and, pairs))

        return compare

    def boolean(self, node: ast.BoolOp, depth: int) -> Fn:
        combine = np.logical_and if isinstance(node.op, ast.And) else np.logical_or
        parts = [self.compile(n, depth + 1) for n in node.values]
        return lambda env: _float(reduce(combine, [p(env) != 0 for p in parts]))

    def function(self, node: ast.Call, depth: int) -> Fn:
        if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
            only = ", ".join(FUNCTIONS)
            raise self.fail(node.func, f"only these functions may be called: {only}")
        if node.keywords:
            raise self.fail(node.keywords[0], "keyword arguments are not allowed")
        fn, least, most = FUNCTIONS[node.func.id]
        if not least <= len(node.args) <= most:
            count = str(least) if least == most else f"{least} to {most}"
            noun = "argument" if most == 1 else "arguments"
            raise self.fail(node, f"{node.func.id}() takes {count} {noun}")
        return self.call(fn, node.args, depth)

    def call(self, fn: Callable[..., Any], args: list[ast.expr], depth: int) -> Fn:
        parts = [self.compile(a, depth + 1) for a in args]
        return lambda env: _float(fn(*(p(env) for p in parts)))


def describe(node: ast.AST) -> str:
    """A readable name for a node kind."""
    if isinstance(node, ast.Constant):
        return "a string" if isinstance(node.value, str | bytes) else f"the constant {node.value!r}"
    if isinstance(node, ast.ListComp | ast.SetComp | ast.DictComp | ast.GeneratorExp):
        return "a comprehension"
    kinds = {ast.Attribute: "attribute access", ast.Subscript: "subscripting"}
    kinds |= {ast.JoinedStr: "a string", ast.NamedExpr: "assignment", ast.Starred: "unpacking"}
    return kinds.get(type(node), type(node).__name__.lower())


def compile_expression(text: str, signals: set[str] | None = None) -> tuple[Fn, list[str]]:
    """The expression as a closure over numpy arrays, and the signal names it reads."""
    if len(text) > MAX_LENGTH:
        raise BlueprintError(f"the expression is longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as e:
        raise BlueprintError(f"syntax error at column {(e.offset or 1) - 1}: {e.msg}") from e
    except ValueError as e:  # a null byte, on Python < 3.12
        raise BlueprintError(f"invalid expression: {e}") from e
    except (RecursionError, MemoryError) as err:
        raise BlueprintError(f"the expression is nested more than {MAX_DEPTH} deep") from err
    compiler = _Compiler(text.strip(), signals)
    return compiler.compile(tree.body), list(compiler.names)


def check_expression(text: str) -> list[str]:
    """The free names (signals) of an expression; BlueprintError says what is wrong with it."""
    return compile_expression(text)[1]


class ExpressionParams(Params):
    outputs: dict[str, str] = Field(
        min_length=1,
        description="Output signal name -> expression of numbers, signals, pi, e, nan, inf, "
        "+ - * / // % **, comparisons, and / or / not, `a if c else b` and the functions "
        + ", ".join(FUNCTIONS),
    )
    signals: list[str] | None = Field(
        None,
        description="The signals the expressions may use (a misspelt name is then an error); "
        "empty: every name an expression uses is an input signal.",
    )


def compile_outputs(params: ExpressionParams) -> tuple[dict[str, Fn], list[str]]:
    """Each output's closure and the inputs of them all, in order of first use."""
    allowed = set(params.signals) if params.signals is not None else None
    compiled: dict[str, Fn] = {}
    names: dict[str, None] = {}
    for output, text in params.outputs.items():
        if not output:
            raise BlueprintError("an output needs a name")
        try:
            compiled[output], used = compile_expression(text, allowed)
        except BlueprintError as e:
            raise BlueprintError(f"output {output!r}: {e}") from e
        names.update(dict.fromkeys(used))
    return compiled, list(names)


class Expression(Blueprint[ExpressionParams]):
    """Derived signals (expressions)

    Computes new signals from formulas over the input signals, sample by sample, e.g.
    `force * 0.3 / 2.1e-12 * 5e-4`, `sqrt(ax**2 + ay**2)` or `where(angle > 0.5, 1, 0)`.
    Comparisons and and / or / not give 1 or 0; in `a if c else b` both branches are computed.
    A missing signal is NaN, which spreads through arithmetic; samples where every output is
    NaN give no output. Division by zero gives inf or nan. Signal names must be identifiers
    (the processor's input mapping gives them those names).
    """

    name = "expression"
    Params = ExpressionParams
    keeps_state = True

    def __init__(self, params: ExpressionParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._compiled, self._inputs = compile_outputs(params)

    @classmethod
    def check(cls, params: Any) -> None:
        compile_outputs(params)

    def inputs(self) -> list[str]:
        return list(self._inputs)

    def outputs(self) -> list[str]:
        return list(self.params.outputs)

    def reconfigure(self, params: ExpressionParams) -> bool:
        """Takes new expressions in place (there is no state to lose)."""
        self._compiled, self._inputs = compile_outputs(params)
        self.params = params
        return True

    def process(self, batch: Batch) -> Batch | None:
        n = len(batch)
        missing = np.full(n, np.nan)
        env = {name: batch.columns.get(name, missing) for name in self._inputs}
        with np.errstate(all="ignore"):
            out = {
                k: np.broadcast_to(f(env), (n,)).astype(np.float64)
                for k, f in self._compiled.items()
            }
        keep = np.any([~np.isnan(v) for v in out.values()], axis=0)
        if not keep.any():
            return None
        if keep.all():
            return batch.with_columns(out)
        return Batch(batch.times[keep], {k: v[keep] for k, v in out.items()})
