"""Reading a sample batch from the wire: per-sample rejection, values, and the checks
against a twin's interface."""

from __future__ import annotations

from typing import Any

import pytest
import yaml

from tests.unit._samples import (
    NOW,
    T2024,
    TINGEN,
    num,
    one,
    read,
    reason,
    schema,
)
from twinlink.domain.jsontext import int64_problem, loads
from twinlink.domain.samples import (
    MAX_STRING,
    OPEN_SCHEMA,
    SignalRule,
    big_int_outside_samples,
    read_batch,
    schema_from_interface,
)

# --- per-sample rejection ---------------------------------------------------------------------


def test_bad_samples_are_rejected_with_index_and_reason_and_the_rest_kept() -> None:
    out = read(
        [
            {"time": T2024, "values": {"a": 1}},
            "not a sample",
            {"time": T2024 + 1, "values": {"a": float("nan")}},
            {"time": T2024 + 2, "values": {"a": 3}},
            {"time": "noon", "values": {"a": 4}},
            {"values": {"b": 5}},
        ],
        time_unit="s",
    )
    assert out.times == [T2024 * 10**9, (T2024 + 2) * 10**9, NOW]
    assert out.values == [{"a": 1}, {"a": 3}, {"b": 5}]
    assert [(r.index, r.reason) for r in out.rejected] == [
        (1, "a sample is an object with `values` and an optional `time`"),
        (2, "a: nan is not a finite number"),
        (4, "`time` 'noon' is not an ISO 8601 time"),
    ]
    assert out.server_timed == 1


def test_every_rejection_is_listed() -> None:
    out = read([{"values": {}}] * 250)
    assert [r.index for r in out.rejected] == list(range(250))


@pytest.mark.parametrize("sample", [None, 1, "x", [{"values": {"a": 1}}]])
def test_a_sample_must_be_an_object(sample: Any) -> None:
    out = read([sample])
    assert out.rejected[0].reason == "a sample is an object with `values` and an optional `time`"


@pytest.mark.parametrize("sample", [{}, {"values": {}}, {"values": [1]}, {"values": None}])
def test_a_sample_needs_at_least_one_value(sample: dict[str, Any]) -> None:
    assert reason(sample) == "`values` must be an object with at least one signal"


def test_values_are_checked_before_time() -> None:
    assert reason({"time": "noon"}) == "`values` must be an object with at least one signal"


# --- values -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name", ["a", "A", "_", "Tip_Angular_Rate_Y_radps", "imu.acc:x-1", "a" * 128]
)
def test_valid_signal_names(name: str) -> None:
    assert one({"values": {name: 1}}).values == [{name: 1}]


@pytest.mark.parametrize("name", ["", "1a", ".a", "-a", "a b", "a/b", "ä", "a" * 129])
def test_invalid_signal_names_are_rejected(name: str) -> None:
    assert reason({"values": {name: 1}}).startswith(f"signal name {name!r} must match ^[A-Za-z_]")


@pytest.mark.parametrize(
    "value",
    [0, -1, 2**63 - 1, -(2**63), 1.5, -0.0, 1e308, True, False, "", "x" * MAX_STRING],
)
def test_numbers_bools_and_strings_are_kept_as_sent(value: Any) -> None:
    out = one({"values": {"v": value}})
    assert out.values == [{"v": value}]
    assert type(out.values[0]["v"]) is type(value)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (None, "v: None is not a number, bool or string"),
        ([1, 2], "v: [1, 2] is not a number, bool or string"),
        ({"x": 1}, "v: {'x': 1} is not a number, bool or string"),
        (float("nan"), "v: nan is not a finite number"),
        (float("inf"), "v: inf is not a finite number"),
        (float("-inf"), "v: -inf is not a finite number"),
        (2**63, f"v: {int64_problem(2**63)}"),
        (-(2**63) - 1, f"v: {int64_problem(-(2**63) - 1)}"),
        (10**30, f"v: {int64_problem(10**30)}"),
        ("x" * (MAX_STRING + 1), "v: a string value holds at most 1024 characters"),
    ],
)
def test_values_that_cannot_be_stored_are_rejected(value: Any, message: str) -> None:
    assert reason({"values": {"v": value}}) == message


def test_integers_beyond_64_bits_sent_as_json_are_rejected_not_rounded() -> None:
    # Read as the transports read it: exact, so 2**80 is refused instead of stored as 1.2e24.
    body = loads(
        f'{{"seq": 1, "samples": [{{"values": {{"a": {2**80}}}}}, {{"values": {{"a": 5}}}},'
        f' {{"values": {{"a": {-(2**63)}, "b": {2**63 - 1}}}}}]}}'
    )
    out = read_batch(body, OPEN_SCHEMA, NOW)
    assert out.values == [{"a": 5}, {"a": -(2**63), "b": 2**63 - 1}]
    assert [(r.index, r.reason) for r in out.rejected] == [(0, f"a: {int64_problem(2**80)}")]


def test_a_device_message_is_refused_for_a_big_integer_outside_its_samples() -> None:
    inside = {"type": "samples", "seq": 1, "samples": [{"values": {"a": 2**80}}]}
    assert big_int_outside_samples(inside) is None  # the sample's own business
    assert big_int_outside_samples({"type": "samples", "seq": 2**64, "samples": []}) == (
        f"seq: {int64_problem(2**64)}"
    )
    reported = {"type": "reported", "id": 3, "properties": {"rate": 5, "n": -(2**70)}}
    assert big_int_outside_samples(reported) == f"properties.n: {int64_problem(-(2**70))}"
    result = {"type": "result", "id": "c1", "status": "succeeded", "result": [0, {"x": 2**63}]}
    assert big_int_outside_samples(result) == f"result[1].x: {int64_problem(2**63)}"


def test_long_values_are_shortened_in_the_message() -> None:
    message = reason({"values": {"v": list(range(100))}})
    shown = message.removeprefix("v: ").removesuffix(" is not a number, bool or string")
    assert len(shown) == 40
    assert shown == repr(list(range(100)))[:37] + "..."


def test_one_bad_value_rejects_the_whole_sample() -> None:
    out = one({"values": {"good": 1, "bad": None}})
    assert out.values == []
    assert out.rejected[0].reason == "bad: None is not a number, bool or string"


# --- interface checks -------------------------------------------------------------------------


def test_number_accepts_ints_and_floats_but_not_bools_or_strings() -> None:
    rules = schema(x=num())
    assert one({"values": {"x": 1}}, rules).values == [{"x": 1}]
    assert one({"values": {"x": 1.5}}, rules).values == [{"x": 1.5}]
    assert reason({"values": {"x": True}}, rules) == "x: True is not a number"
    assert reason({"values": {"x": False}}, rules) == "x: False is not a number"
    assert reason({"values": {"x": "1"}}, rules) == "x: '1' is not a number"


def test_integer_accepts_only_ints() -> None:
    rules = schema(n=SignalRule("integer", None, None))
    assert one({"values": {"n": 3}}, rules).values == [{"n": 3}]
    assert reason({"values": {"n": 3.0}}, rules) == "n: 3.0 is not an integer"
    assert reason({"values": {"n": True}}, rules) == "n: True is not an integer"
    assert reason({"values": {"n": "3"}}, rules) == "n: '3' is not an integer"


def test_bool_and_string_types() -> None:
    rules = schema(on=SignalRule("bool", None, None), id=SignalRule("string", None, None))
    assert one({"values": {"on": False, "id": "x"}}, rules).values == [{"on": False, "id": "x"}]
    assert reason({"values": {"on": 1}}, rules) == "on: 1 is not a bool"
    assert reason({"values": {"on": "true"}}, rules) == "on: 'true' is not a bool"
    assert reason({"values": {"id": 1}}, rules) == "id: 1 is not a string"
    assert reason({"values": {"id": False}}, rules) == "id: False is not a string"


def test_min_and_max_are_inclusive_and_out_of_range_is_rejected_by_default() -> None:
    rules = schema(x=num(0.0, 1.0), n=SignalRule("integer", -5, 5))
    assert one({"values": {"x": 0.0, "n": -5}}, rules).rejected == []
    assert one({"values": {"x": 1.0, "n": 5}}, rules).rejected == []
    assert reason({"values": {"x": -0.001}}, rules) == "x: -0.001 is below the minimum 0.0"
    assert reason({"values": {"x": 1.5}}, rules) == "x: 1.5 is above the maximum 1.0"
    assert reason({"values": {"n": 6}}, rules) == "n: 6 is above the maximum 5"
    assert reason({"values": {"n": -6}}, rules) == "n: -6 is below the minimum -5"


def test_only_one_bound_may_be_given() -> None:
    low = schema(x=num(lo=0))
    assert one({"values": {"x": 1e300}}, low).rejected == []
    assert reason({"values": {"x": -1}}, low) == "x: -1 is below the minimum 0"
    high = schema(x=num(hi=0))
    assert one({"values": {"x": -1e300}}, high).rejected == []
    assert reason({"values": {"x": 1}}, high) == "x: 1 is above the maximum 0"


def test_out_of_range_accept_keeps_the_value_but_still_checks_the_type() -> None:
    rules = schema(out_of_range="accept", x=num(0, 1))
    out = read([{"values": {"x": 99}}, {"values": {"x": -99.5}}], rules)
    assert out.values == [{"x": 99}, {"x": -99.5}]
    assert out.rejected == []
    assert reason({"values": {"x": True}}, rules) == "x: True is not a number"


def test_a_range_on_a_bool_signal_does_not_apply() -> None:
    rules = schema(on=SignalRule("bool", 2, 3))
    assert one({"values": {"on": True}}, rules).values == [{"on": True}]


def test_unknown_signals_are_accepted_by_default() -> None:
    rules = schema(x=num(0, 1))
    out = one({"values": {"x": 0.5, "extra": "anything"}}, rules)
    assert out.values == [{"x": 0.5, "extra": "anything"}]
    assert out.dropped == 0
    # an accepted unknown signal alone is enough to keep the sample
    assert one({"values": {"extra": 1}}, rules).values == [{"extra": 1}]


def test_unknown_signals_still_need_a_storable_value() -> None:
    rules = schema(x=num(0, 1))
    assert reason({"values": {"x": 0.5, "extra": None}}, rules) == (
        "extra: None is not a number, bool or string"
    )


def test_unknown_signals_dropped_are_counted() -> None:
    rules = schema("drop", x=num(0, 1))
    out = read(
        [
            {"values": {"x": 0.1, "y": 1, "z": 2}},
            {"values": {"x": 0.2}},
            {"values": {"w": 3, "x": 0.3}},
        ],
        rules,
    )
    assert out.values == [{"x": 0.1}, {"x": 0.2}, {"x": 0.3}]
    assert out.dropped == 3
    assert out.rejected == []


def test_a_sample_left_with_no_known_signal_is_rejected() -> None:
    rules = schema("drop", x=num(0, 1))
    out = read([{"values": {"y": 1}}, {"values": {"x": 0.5}}], rules)
    assert out.values == [{"x": 0.5}]
    assert [(r.index, r.reason) for r in out.rejected] == [
        (0, "no signal of this twin's interface is in `values`")
    ]


def test_drops_of_a_rejected_sample_are_not_counted() -> None:
    rules = schema("drop", x=num(0, 1))
    out = one({"values": {"y": 1, "x": 5}}, rules)
    assert out.rejected[0].reason == "x: 5 is above the maximum 1"
    assert out.dropped == 0


def test_unknown_signals_rejected_reject_the_sample() -> None:
    rules = schema("reject", x=num(0, 1))
    out = read([{"values": {"x": 0.1, "y": 1}}, {"values": {"x": 0.2}}], rules)
    assert out.values == [{"x": 0.2}]
    assert [(r.index, r.reason) for r in out.rejected] == [
        (0, "y: not a signal of this twin's interface")
    ]


def test_an_empty_interface_that_rejects_unknown_signals_accepts_nothing() -> None:
    rules = schema("reject")
    assert not rules.is_open
    assert reason({"values": {"a": 1}}, rules) == "a: not a signal of this twin's interface"
    assert reason({"values": {"a": 1}}, schema("drop")) == (
        "no signal of this twin's interface is in `values`"
    )


def test_the_open_schema_accepts_any_valid_signal() -> None:
    assert OPEN_SCHEMA.is_open
    assert not schema(x=num()).is_open
    assert schema().is_open


# --- schema from a DT document's interface ----------------------------------------------------


@pytest.mark.parametrize("interface", [None, {}])
def test_no_interface_means_the_open_schema(interface: Any) -> None:
    assert schema_from_interface(interface) is OPEN_SCHEMA


def test_schema_from_the_tingen_interface() -> None:
    interface = yaml.safe_load(TINGEN.read_text(encoding="utf-8"))["interface"]
    rules = schema_from_interface(interface)
    assert rules.signals == {
        "Cantilever_Angle_radians": SignalRule("number", 0.0, 1.0),
        "Input_F_in": SignalRule("number", 0.0, 10.0),
        "Tip_Acceleration_X_mps2": SignalRule("number", -19.62, 19.62),
        "Tip_Angular_Rate_Y_radps": SignalRule("number", -4.2761, 4.2761),
    }
    # properties and commands are not signals
    assert "sample_rate" not in rules.signals
    assert (rules.unknown_signals, rules.out_of_range) == ("accept", "reject")
    assert not rules.is_open
    out = read(
        [
            {"values": {"Cantilever_Angle_radians": 0.8, "Input_F_in": 7.8}},
            {"values": {"Cantilever_Angle_radians": 1.2}},
            {"values": {"Tip_Acceleration_X_mps2": -20.0}},
            {"values": {"Input_F_in": "7.8"}},
        ],
        rules,
    )
    assert out.values == [{"Cantilever_Angle_radians": 0.8, "Input_F_in": 7.8}]
    assert [r.reason for r in out.rejected] == [
        "Cantilever_Angle_radians: 1.2 is above the maximum 1.0",
        "Tip_Acceleration_X_mps2: -20.0 is below the minimum -19.62",
        "Input_F_in: '7.8' is not a number",
    ]


def test_schema_defaults_and_policies_from_the_interface() -> None:
    rules = schema_from_interface(
        {
            "signals": [
                {"name": "plain"},
                {"name": "count", "type": "integer", "min": 0},
                "not a signal",
                {"type": "number"},
                {"name": 5},
            ],
            "unknown_signals": "drop",
            "out_of_range": "accept",
        }
    )
    assert rules.signals == {
        "plain": SignalRule("number", None, None),
        "count": SignalRule("integer", 0, None),
    }
    assert (rules.unknown_signals, rules.out_of_range) == ("drop", "accept")


def test_an_interface_without_signals_keeps_its_policy() -> None:
    rules = schema_from_interface({"signals": None, "unknown_signals": "reject"})
    assert rules.signals == {}
    assert reason({"values": {"a": 1}}, rules) == "a: not a signal of this twin's interface"
    assert schema_from_interface({"commands": []}).is_open
