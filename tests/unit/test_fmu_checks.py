"""The FMI rules an fmu processor's params are checked by (processors/fmurules.py), on
variables as an upload's inspection keeps them (FmuInfo.as_dict)."""

from __future__ import annotations

from typing import Any

import pytest

from twinlink.domain.errors import InvalidInputError
from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.blueprints._fmu_fmi import value_for
from twinlink.processors.fmuinfo import FmuVariable
from twinlink.processors.fmurules import check_fmu_params, value_problem


def var(name: str, type_: str, **extra: Any) -> dict[str, Any]:
    base = {"causality": "parameter", "variability": "fixed", "initial": "exact", "shape": []}
    return {"name": name, "type": type_, **base, **extra}


@pytest.mark.parametrize(
    ("variable", "value", "fmi3", "words"),
    [
        (var("a", "UInt8"), 300, True, "outside the range of UInt8 [0, 255]"),
        (var("a", "UInt8"), -1, True, "outside the range of UInt8"),
        (var("a", "UInt32"), -1, True, "outside the range of UInt32 [0, 4294967295]"),
        (var("a", "Int16"), 40000, True, "outside the range of Int16"),
        (var("a", "UInt64"), 2**64, True, "outside the range of UInt64"),
        (var("a", "Integer"), 2**31, False, "outside the range of Integer"),
        (var("a", "Integer"), 2.5, False, "not a whole number"),
        (var("a", "Integer"), True, False, "not a number"),
        (var("a", "Integer"), "3", False, "not a number"),
        (var("a", "Int32", min=0.0, max=5.0), 6, True, "declared range [0, 5]"),
        (var("a", "Float64"), float("nan"), True, "not a finite number"),
        (var("a", "Float32"), 1e39, True, "range of Float32"),
        (var("a", "Real", min=-1.0), -2.0, False, "declared range [-1, ]"),
        (var("a", "Boolean"), 1, False, "true or false"),
        (var("a", "Boolean"), "yes", False, "true or false"),
        (var("a", "String"), 5, False, "not a string"),
        (var("a", "Enumeration", items=[{"name": "x", "value": 1}]), 2, False, "x (1)"),
        (var("a", "Enumeration", items=[{"name": "x", "value": 1}]), "y", False, "not an item"),
        (var("a", "Enumeration"), 2**31, False, "range of an enumeration"),
        (var("a", "Binary"), "00", True, "cannot be set"),
    ],
)
def test_values_that_do_not_fit_their_type_are_named(
    variable: dict[str, Any], value: Any, fmi3: bool, words: str
) -> None:
    problem = value_problem(variable, value, fmi3)
    assert problem is not None and words in problem, problem


@pytest.mark.parametrize(
    ("variable", "value"),
    [
        (var("a", "UInt8"), 255),
        (var("a", "UInt64"), 2**64 - 1),
        (var("a", "Int64"), -(2**63)),
        (var("a", "Integer"), 3.0),
        (var("a", "Boolean"), True),
        (var("a", "Boolean"), "false"),
        (var("a", "Enumeration", items=[{"name": "x", "value": 1}]), "x"),
        (var("a", "Enumeration", items=[{"name": "x", "value": 1}]), 1),
        (var("a", "Enumeration"), 7),  # a description kept before items were: any int32
        (var("a", "Float32"), 1.5),
        (var("a", "String"), "text"),
    ],
)
def test_values_that_fit_pass(variable: dict[str, Any], value: Any) -> None:
    assert value_problem(variable, value, fmi3=True) is None


INFO = {
    "fmi_version": "2.0",
    "variables": [
        var("u", "Real", causality="input", variability="continuous", initial=None),
        var("v", "Real", causality="input", variability="continuous", initial=None),
        var("y", "Real", causality="output", variability="continuous", initial="calculated"),
        var("s", "Real", causality="local", variability="continuous", initial="exact"),
        var("arr", "Float64", causality="input", shape=[3]),
    ],
}


@pytest.mark.parametrize(
    ("params", "mapped", "words"),
    [
        ({"parameters": {"y": 1.0}}, [], "y: it is calculated by the FMU (output"),
        ({"inputs": ["arr"]}, [], "arr: it is an array"),
        ({"outputs": ["arr"]}, [], "arr: it is an array"),
        ({"inputs": ["u"]}, ["v"], "inputs: v is not an input the processor streams"),
        ({}, ["w"], "(it streams: u, v)"),
    ],
)
def test_params_the_fmu_cannot_run_are_refused(
    params: dict[str, Any], mapped: list[str], words: str
) -> None:
    with pytest.raises(InvalidInputError) as err:
        check_fmu_params(params, mapped, INFO, "m.fmu")
    assert words in str(err.value)


def test_start_values_of_inputs_and_exact_locals_may_be_set() -> None:
    check_fmu_params({"parameters": {"u": 1.0, "s": 2.0}}, ["u", "v"], INFO, "m.fmu")


@pytest.mark.parametrize(("type_", "value"), [("UInt8", 300), ("UInt32", -1), ("Integer", 2**31)])
def test_the_worker_refuses_what_would_wrap_around(type_: str, value: int) -> None:
    """A processor stored before these checks: its worker refuses the value, not wraps it."""
    variable = FmuVariable("a", 1, "parameter", "fixed", type_, initial="exact")
    with pytest.raises(BlueprintError, match=f"outside the range of {type_}"):
        value_for(variable, value)
    assert value_for(variable, 1) == 1
