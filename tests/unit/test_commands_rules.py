"""Command arguments and property values checked against a twin's `interface`."""

from __future__ import annotations

from typing import Any

import pytest

from twinlink.cli.commands import parse_assignments
from twinlink.commands.rules import (
    OPEN_RULES,
    check_command,
    check_desired,
    check_reported,
    rules_from_interface,
)
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.jsontext import int64_problem
from twinlink.domain.properties import same_value

RULES = rules_from_interface(
    {
        "commands": [
            {"name": "pause"},
            {
                "name": "move",
                "parameters": [
                    {"name": "x", "type": "number", "min": -1, "max": 1, "required": True},
                    {"name": "steps", "type": "integer", "default": 10},
                    {"name": "fast", "type": "bool"},
                    {"name": "label", "type": "string", "default": "m"},
                    {"name": "anything"},  # no type: number
                ],
            },
        ],
        "properties": [
            {"name": "rate", "min": 1, "max": 100, "writable": True},
            {"name": "mode", "type": "string", "writable": True},
            {"name": "paused", "type": "bool"},
        ],
    }
)


def test_defaults_are_filled_in_and_given_values_kept() -> None:
    assert check_command(RULES, "move", {"x": 0.5}) == {"x": 0.5, "steps": 10, "label": "m"}
    assert check_command(RULES, "move", {"x": 1, "steps": 3, "fast": True}) == {
        "x": 1, "steps": 3, "fast": True, "label": "m",
    }  # fmt: skip
    assert check_command(RULES, "pause", None) == {}


@pytest.mark.parametrize(
    ("name", "args", "reason"),
    [
        ("jump", {}, "the twin has no command 'jump'; its commands are: move, pause"),
        ("move", {}, "move: the argument 'x' is required"),
        ("move", {"x": 2}, "move: argument 'x': 2 is above the maximum 1"),
        ("move", {"x": -1.5}, "-1.5 is below the minimum -1"),
        ("move", {"x": True}, "'x': true is not a number"),
        ("move", {"x": 0, "steps": 2.0}, "'steps': 2.0 is not an integer"),
        ("move", {"x": 0, "fast": "yes"}, "'fast': \"yes\" is not a bool"),
        ("move", {"x": 0, "label": 5}, "'label': 5 is not a string"),
        ("move", {"x": 0, "y": 1}, "move: unknown argument 'y'; it takes x, steps, fast"),
        ("pause", {"now": 1}, "pause: unknown argument 'now'; it takes no arguments"),
        ("move", [1], "`args` must be a JSON object"),
        ("", {}, "command name '' must match"),
        (5, {}, "command name 5 must match"),
    ],
)
def test_wrong_commands_say_why(name: Any, args: Any, reason: str) -> None:
    with pytest.raises(InvalidInputError) as err:
        check_command(RULES, name, args)
    assert reason in str(err.value)


def test_a_twin_without_commands_takes_any_name_and_json_args() -> None:
    args = {"nested": {"list": [1, None, "x"]}}
    assert check_command(OPEN_RULES, "whatever", args) == args
    with pytest.raises(InvalidInputError, match="at most"):
        check_command(OPEN_RULES, "big", {"blob": "x" * 70_000})


@pytest.mark.parametrize("rules", [OPEN_RULES, RULES], ids=["open", "declared"])
@pytest.mark.parametrize("n", [2**63, -(2**63) - 1, 2**64, 2**80])
def test_arguments_beyond_64_bits_are_refused_with_their_place(rules: Any, n: int) -> None:
    # Anywhere in the arguments, before orjson (which cannot write them) ever sees them.
    for args, place in [
        ({"x": n}, "args.x"),
        ({"x": 0.5, "steps": [1, {"deep": n}]}, "args.steps[1].deep"),
    ]:
        with pytest.raises(InvalidInputError) as err:
            check_command(rules, "move", args)
        assert str(err.value) == f"move: {place}: {int64_problem(n)}"


def test_arguments_at_the_64_bit_bounds_are_kept() -> None:
    args = {"low": -(2**63), "high": 2**63 - 1}
    assert check_command(OPEN_RULES, "edges", args) == args


@pytest.mark.parametrize("n", [2**63, -(2**63) - 1, 10**30])
def test_property_values_beyond_64_bits_get_the_one_message(n: int) -> None:
    with pytest.raises(InvalidInputError) as err:
        check_desired(RULES, {"rate": n})
    assert str(err.value) == f"desired rate: {int64_problem(n)}"
    with pytest.raises(InvalidInputError) as err:
        check_reported(OPEN_RULES, {"count": n})
    assert str(err.value) == f"reported count: {int64_problem(n)}"


def test_desired_values_must_be_writable_known_and_in_range() -> None:
    assert check_desired(RULES, {"rate": 50, "mode": None}) == {"rate": 50, "mode": None}
    for body, reason in [
        ({"paused": True}, "'paused' is not writable"),
        ({"speed": 1}, "no property 'speed'; its properties: mode, paused, rate"),
        ({"rate": 0}, "0 is below the minimum 1"),
        ({"rate": float("nan")}, "is not a finite number"),
        ({"mode": 1}, "is not a string"),
        ({"mode": "x" * 2000}, "at most 1024 characters"),
        ({"bad name": 1}, "must match"),
        ({}, "JSON object"),
        ([], "JSON object"),
    ]:
        with pytest.raises(InvalidInputError) as err:
            check_desired(RULES, body)
        assert reason in str(err.value), body


def test_reported_values_are_type_checked_but_not_range_checked() -> None:
    assert check_reported(RULES, {"rate": 500, "paused": False}) == {"rate": 500, "paused": False}
    with pytest.raises(InvalidInputError, match="not a bool"):
        check_reported(RULES, {"paused": 0})
    with pytest.raises(InvalidInputError, match="not a property"):
        check_reported(RULES, {"other": 0})
    assert check_reported(OPEN_RULES, {"other": "x"}) == {"other": "x"}
    with pytest.raises(InvalidInputError, match="not a number, bool or string"):
        check_reported(OPEN_RULES, {"other": None})


def test_same_value_compares_as_json() -> None:
    assert same_value(1, 1.0)
    assert not same_value(True, 1)
    assert not same_value("1", 1)
    assert same_value(False, False)


def test_cli_assignments_are_json_when_they_parse() -> None:
    assert parse_assignments(("a=50", "b=true", "c=fast", 'd="50"', "e=null", "f=[1,2]", "g=")) == {
        "a": 50, "b": True, "c": "fast", "d": "50", "e": None, "f": [1, 2], "g": "",
    }  # fmt: skip
    with pytest.raises(Exception, match="not key=value"):
        parse_assignments(("novalue",))
    # Exact, for the server to refuse with its message (orjson sent 1.2089258196146292e+24).
    assert parse_assignments((f"v={2**80}", "w=NaN")) == {"v": 2**80, "w": "NaN"}
