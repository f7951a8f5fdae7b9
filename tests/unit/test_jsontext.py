"""JSON read exactly: integers beyond 64 bits refused with one message, duplicate keys in
documents refused with their line, syntax errors with their position."""

from __future__ import annotations

import pytest

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.jsontext import (
    INT64_MAX,
    INT64_MIN,
    JsonTextError,
    check_int64,
    first_big_int,
    int64_problem,
    loads,
    loads_document,
)


@pytest.mark.parametrize("n", [2**63, 2**64, 2**80, -(2**63) - 1, -(2**70)])
def test_integers_stay_exact_so_they_can_be_refused(n: int) -> None:
    value = loads(f'{{"x": [1, {n}]}}')
    assert value == {"x": [1, n]}  # never a float
    assert first_big_int(value) == ("x[1]", n)
    with pytest.raises(InvalidInputError, match="does not fit in 64 bits"):
        check_int64(value, "args")


def test_int64_bounds_are_accepted() -> None:
    value = loads(f"[{INT64_MIN}, {INT64_MAX}, 1.5, true, null]")
    check_int64(value)
    assert value == [INT64_MIN, INT64_MAX, 1.5, True, None]


def test_an_integer_python_cannot_print_is_refused_with_the_same_message() -> None:
    with pytest.raises(JsonTextError, match="does not fit in 64 bits") as err:
        loads("[" + "7" * 5000 + "]")
    assert "5000 digits" in str(err.value)
    assert len(str(err.value)) < 200


def test_the_message_is_short_for_long_numbers() -> None:
    text = int64_problem(10**100)
    assert "101 digits" in text and text.startswith("100000000000...000000")


@pytest.mark.parametrize(
    ("text", "line", "column"),
    [('{\n  "a": 1\n  "b": 2}', 3, 3), ("[1,\n 2,, 3]", 2, 4)],
)
def test_syntax_errors_name_line_and_column(text: str, line: int, column: int) -> None:
    with pytest.raises(JsonTextError) as err:
        loads(text)
    assert (err.value.line, err.value.column) == (line, column)


@pytest.mark.parametrize(
    "text", ['{"a": NaN}', '{"a": 1e999}', "[1,", '"\\ud800"', "[" * 5000 + "]" * 5000]
)
def test_other_bad_json_is_refused(text: str) -> None:
    with pytest.raises(JsonTextError):
        loads(text)


def test_documents_refuse_duplicate_keys_with_their_line() -> None:
    text = '{\n  "name": "a",\n  "features": [{"name": "x",\n    "name": "y"}]\n}'
    with pytest.raises(JsonTextError, match="'name' is given twice") as err:
        loads_document(text)
    assert err.value.line == 4


def test_documents_refuse_big_integers_with_their_path() -> None:
    with pytest.raises(JsonTextError, match=r"createdMachine: 9300000000000000000000 does not"):
        loads_document('{"createdMachine": 9300000000000000000000}')


def test_plain_loads_keeps_the_last_duplicate() -> None:
    # Telemetry and messages are not documents: no second parse on the hot path.
    assert loads('{"a": 1, "a": 2}') == {"a": 2}
