"""OPC UA values and the platform's: a notification's value and time (or why it is not
stored), command arguments as Variants of a node's data type, and the batches notifications
are gathered into."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest
from asyncua import ua
from asyncua.ua.status_codes import StatusCodes

from twinlink.connectors.opcua.values import (
    Reading,
    SampleBatcher,
    ValueRefused,
    json_value,
    platform_value,
    read_data_value,
    variant_for,
)
from twinlink.domain.jsontext import int64_problem

ARRIVAL = 1_800_000_000_000_000_000
SOURCE = datetime(2025, 3, 4, 5, 6, 7, 123456, tzinfo=UTC)
SOURCE_NS = 1_741_064_767_123_456_000
SERVER = datetime(2025, 3, 4, 5, 6, 8, tzinfo=UTC)
SERVER_NS = 1_741_064_768_000_000_000
V = ua.VariantType


def data(
    value: Any = 1.5,
    source: datetime | None = SOURCE,
    server: datetime | None = SERVER,
    code: int = 0,
) -> ua.DataValue:
    def stamp(when: datetime | None) -> ua.DateTime | None:
        return None if when is None else ua.DateTime.combine(when.date(), when.timetz())

    return ua.DataValue(
        ua.Variant(value),
        StatusCode=ua.StatusCode(ua.UInt32(code)),
        SourceTimestamp=stamp(source),
        ServerTimestamp=stamp(server),
    )


@pytest.mark.parametrize(
    ("source", "server", "time_ns"),
    [
        (SOURCE, SERVER, SOURCE_NS),
        (None, SERVER, SERVER_NS),
        (None, None, ARRIVAL),
        (datetime(1601, 1, 1, tzinfo=UTC), SERVER, SERVER_NS),  # OPC UA's null time
        (SOURCE.replace(tzinfo=None), None, SOURCE_NS),  # naive means UTC
    ],
)
def test_the_sample_time_is_the_source_time_else_the_servers_else_the_arrival(
    source: datetime | None, server: datetime | None, time_ns: int
) -> None:
    assert read_data_value(data(source=source, server=server), ARRIVAL) == Reading(time_ns, 1.5)


def test_a_bad_status_is_an_error_and_an_uncertain_one_a_value() -> None:
    bad = read_data_value(data(None, code=StatusCodes.BadSensorFailure), ARRIVAL)
    assert bad == Reading(SOURCE_NS, error_kind="bad_status", error="BadSensorFailure")
    uncertain = data(2.0, code=StatusCodes.UncertainLastUsableValue)
    assert read_data_value(uncertain, ARRIVAL) == Reading(SOURCE_NS, 2.0)


def test_a_value_of_no_platform_type_is_an_error() -> None:
    reading = read_data_value(data([1.0, 2.0]), ARRIVAL)
    assert (reading.error_kind, reading.error) == (
        "unsupported_value",
        "an array is not a number, bool or string",
    )
    assert read_data_value(None, ARRIVAL).error_kind == "bad_status"


@pytest.mark.parametrize(
    ("raw", "value"),
    [
        (True, True),
        (ua.Int16(-3), -3),
        (ua.UInt64(2**63 - 1), 2**63 - 1),
        (ua.Float(0.5), 0.5),
        ("open", "open"),
        (ua.LocalizedText("Läuft", "de"), "Läuft"),
        (SOURCE, "2025-03-04T05:06:07.123456Z"),
        (ua.NodeClass.Variable, 2),  # an enumeration is its number
    ],
)
def test_platform_values(raw: Any, value: Any) -> None:
    got = platform_value(raw)
    assert got == value and type(got) is type(value)


@pytest.mark.parametrize(
    ("raw", "why"),
    [
        (2**64 - 1, int64_problem(2**64 - 1)),
        (float("nan"), "nan is not a finite number"),
        ("x" * 1025, "a string of 1025 characters (at most 1024)"),
        (None, "the value is empty (null)"),
        (b"\x00", "a bytes is not a number, bool or string"),
    ],
)
def test_values_the_platform_cannot_store(raw: Any, why: str) -> None:
    with pytest.raises(ValueRefused) as caught:
        platform_value(raw)
    assert str(caught.value) == why


@pytest.mark.parametrize(
    ("value", "vtype", "expected"),
    [
        (0, V.Double, ua.Variant(0.0, V.Double)),
        (0.25, V.Float, ua.Variant(0.25, V.Float)),
        (3.0, V.Int32, ua.Variant(3, V.Int32)),
        (255, V.Byte, ua.Variant(255, V.Byte)),
        (True, V.Boolean, ua.Variant(True, V.Boolean)),
        ("auto", V.String, ua.Variant("auto", V.String)),
        ("auto", V.LocalizedText, ua.Variant(ua.LocalizedText("auto"), V.LocalizedText)),
        ("2025-03-04T05:06:07.123456Z", V.DateTime, ua.Variant(SOURCE, V.DateTime)),
        (7, V.Variant, ua.Variant(7, V.Int64)),  # BaseDataType: the value says its type
        (0.5, V.Variant, ua.Variant(0.5, V.Double)),
    ],
)
def test_a_command_argument_becomes_a_variant_of_the_nodes_type(
    value: Any, vtype: ua.VariantType, expected: ua.Variant
) -> None:
    assert variant_for(value, vtype) == expected


@pytest.mark.parametrize(
    ("value", "vtype", "why"),
    [
        (True, V.Double, "True is not a number (Double expected)"),
        ("fast", V.Double, "'fast' is not a number (Double expected)"),
        (2.5, V.Int16, "2.5 is not an integer (Int16 expected)"),
        (256, V.Byte, "256 is outside Byte (0 to 255)"),
        (-1, V.UInt32, "-1 is outside UInt32 (0 to 4294967295)"),
        (1, V.Boolean, "1 is not a bool (Boolean expected)"),
        (1, V.String, "1 is not a string (String expected)"),
        ("noon", V.DateTime, "'noon' is not an ISO 8601 time"),
        ({"a": 1}, V.Variant, "{'a': 1} is not a number, bool or string"),
        (1, V.ExtensionObject, "writing the data type ExtensionObject is not supported"),
    ],
)
def test_an_argument_that_does_not_fit_is_refused(
    value: Any, vtype: ua.VariantType, why: str
) -> None:
    with pytest.raises(ValueRefused) as caught:
        variant_for(value, vtype)
    assert str(caught.value) == why


def test_method_outputs_as_json() -> None:
    assert json_value([1, "a", [True, None]]) == [1, "a", [True, None]]
    assert json_value(ua.QualifiedName("Name", 2)) == "QualifiedName(NamespaceIndex=2, Name='Name')"


async def test_values_of_one_time_share_a_sample_in_arrival_order() -> None:
    batcher = SampleBatcher()
    assert not batcher.has_samples.is_set()
    batcher.add(2, "a", 1.0)
    batcher.add(1, "a", 2.0)
    batcher.add(2, "b", True)
    batcher.add(2, "a", 3.0)  # a second value of `a` at time 2: a sample of its own
    assert batcher.has_samples.is_set() and len(batcher) == 3
    assert batcher.take() == [
        {"time": 2, "values": {"a": 1.0, "b": True}},
        {"time": 1, "values": {"a": 2.0}},
        {"time": 2, "values": {"a": 3.0}},
    ]
    assert len(batcher) == 0 and not batcher.has_samples.is_set()
    batcher.add(2, "a", 4.0)  # after a take, a time starts a new sample
    assert batcher.take() == [{"time": 2, "values": {"a": 4.0}}]
