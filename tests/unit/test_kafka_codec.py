"""The Kafka bus's records (bus/kafka/codec.py) and where a subject goes (bus/kafka/topics.py),
without a broker: the round trip keeps every value and its type, a record that is not the
bus's is refused with a reason, and each twin has its key."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest

from twinlink.bus.kafka.codec import (
    UndecodableRecordError,
    UnencodableMessageError,
    decode,
    encode,
)
from twinlink.bus.kafka.topics import key_of, topic_names, topic_of
from twinlink.domain.samples import SampleBatch, Value

I64_MIN, I64_MAX = -(2**63), 2**63 - 1


def test_a_sample_batch_comes_back_equal_with_every_type_kept() -> None:
    values: list[dict[str, Value]] = [
        {"big": I64_MAX, "small": I64_MIN, "one": 1, "one_f": 1.0, "neg0": -0.0},
        {"flag": True, "text": "ü", "nan_free": 5e-324},
    ]
    sent = SampleBatch(7, "tingen", "telemetry", [I64_MIN, I64_MAX], values, 3, "device:a", None)
    subject, got = decode(encode("samples.7.telemetry", sent))
    assert subject == "samples.7.telemetry"
    assert got == sent
    assert isinstance(got, SampleBatch)
    assert [[type(v) for v in sample.values()] for sample in got.values] == [
        [int, int, int, float, float],
        [bool, str, float],
    ]
    assert got.seq is None


def test_a_batch_record_holds_no_field_names() -> None:
    record = encode("samples.1.t", SampleBatch(1, "t", "t", [1], [{"x": 1}], 2, "", 5))
    fields = [1, "samples.1.t", 1, "t", "t", [1], [{"x": 1}], 2, "", 5]
    assert msgspec.msgpack.decode(record) == fields


PLAIN = [None, 0, I64_MIN, I64_MAX, 2**64 - 1, 0.1, "x", b"\x00\xff", [1, [2, "3"]], {1: "k"}]


@pytest.mark.parametrize("message", [*PLAIN, {"a": {"b": []}}])
def test_plain_data_comes_back_equal(message: object) -> None:
    assert decode(encode("commands.3", message)) == ("commands.3", message)


def test_a_tuple_or_set_comes_back_as_a_list() -> None:
    assert decode(encode("x", [(1, 2), {3}])) == ("x", [[1, 2], [3]])


def test_numpy_scalars_are_written_as_python_numbers() -> None:
    _, got = decode(encode("x", [np.float64(0.5), np.int64(-3), np.bool_(True)]))
    assert got == [0.5, -3, True]
    assert [type(v) for v in got] == [float, int, bool]  # type: ignore[attr-defined]


@pytest.mark.parametrize("message", [object(), 2**64, -(2**63) - 1, {"at": [object()]}])
def test_what_msgpack_cannot_hold_is_refused_with_a_reason(message: object) -> None:
    with pytest.raises(UnencodableMessageError) as caught:
        encode("samples.1.t", message)
    assert caught.value.status == 422
    assert "the message for samples.1.t cannot be sent over Kafka" in str(caught.value)


@pytest.mark.parametrize(
    ("record", "reason"),
    [
        (b"", "not MessagePack"),
        (b"\xc1", "not MessagePack"),
        (msgspec.msgpack.encode({"kind": 0}), "not a [kind, subject, ...] array"),
        (msgspec.msgpack.encode([0, 5, 1]), "not a [kind, subject, ...] array"),
        (msgspec.msgpack.encode([9, "s", 1]), "unknown kind 9 with 3 fields"),
        (msgspec.msgpack.encode([1, "s", 1, 2]), "unknown kind 1 with 4 fields"),
    ],
)
def test_a_record_not_written_by_the_bus_is_refused(record: bytes, reason: str) -> None:
    with pytest.raises(UndecodableRecordError, match=reason.replace("[", r"\[")):
        decode(record)


def test_each_family_has_its_topic_and_the_rest_share_one() -> None:
    assert [topic_of(s, "tl") for s in ("samples.7.t", "commands.7", "command-results.7")] == [
        "tl.samples",
        "tl.commands",
        "tl.command-results",
    ]
    assert topic_of("properties.7", "tl") == "tl.properties"
    assert topic_of("processors.7", "tl") == "tl.processor-events"
    assert topic_of("samplesx.7", "tl") == topic_of("plain", "tl") == "tl.other"
    assert set(topic_names("tl")) == {
        "tl.samples",
        "tl.commands",
        "tl.command-results",
        "tl.properties",
        "tl.processor-events",
        "tl.other",
    }


def test_the_key_is_the_twin() -> None:
    assert key_of("samples.7.telemetry") == key_of("samples.7.imu") == b"7"
    assert key_of("commands.7") == b"7"
    assert key_of("samples.70.telemetry") == b"70"
    assert key_of("plain") is None
    assert key_of("odd.") is None
