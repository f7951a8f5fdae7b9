"""MQTT payloads to protocol messages: the four telemetry forms, results and reports."""

from __future__ import annotations

from typing import Any

import pytest

from twinlink.domain.jsontext import int64_problem
from twinlink.domain.samples import BatchError
from twinlink.ingest.mqtt.payloads import (
    Telemetry,
    read_telemetry,
    reported_message,
    result_message,
)


@pytest.mark.parametrize(
    ("payload", "expected"),
    [
        (b'{"angle": 0.1}', Telemetry([{"values": {"angle": 0.1}}], None, None, None)),
        (b'{"time": 5, "values": {"angle": 0.1}}',
         Telemetry([{"time": 5, "values": {"angle": 0.1}}], None, None, None)),
        (b'[{"values": {"a": 1}}, {"values": {"a": 2}}]',
         Telemetry([{"values": {"a": 1}}, {"values": {"a": 2}}], None, None, None)),
        (b'{"seq": 9, "time_unit": "ms", "samples": [{"time": 5, "values": {"a": 1}}]}',
         Telemetry([{"time": 5, "values": {"a": 1}}], None, 9, "ms")),
        (b'{"samples": []}', Telemetry([], None, None, None)),
    ],
)  # fmt: skip
def test_telemetry_forms(payload: bytes, expected: Telemetry) -> None:
    assert read_telemetry(payload, None) == expected


def test_the_topic_names_the_stream() -> None:
    assert read_telemetry(b'{"a": 1}', "fast").stream == "fast"
    assert read_telemetry(b'{"stream": "fast", "samples": []}', "fast").stream == "fast"
    with pytest.raises(BatchError, match="the topic names stream 'fast', the batch 'slow'"):
        read_telemetry(b'{"stream": "slow", "samples": []}', "fast")


def test_the_message_of_a_batch() -> None:
    batch = read_telemetry(b'{"seq": 3, "stream": "x", "time_unit": "s", "samples": []}', None)
    assert batch.message(3) == {"type": "samples", "seq": 3, "samples": [], "stream": "x",
                                "time_unit": "s"}  # fmt: skip


@pytest.mark.parametrize(
    ("payload", "why"),
    [
        (b"not json", "not JSON"),
        (b"0.1", "a JSON object"),
        (b"{}", "a JSON object"),
        (b'{"seq": "1", "samples": []}', "`seq` must be an integer"),
        (b'{"seq": true, "samples": []}', "`seq` must be an integer"),
        (b'{"samples": 5}', "`samples` must be a list"),
    ],
)
def test_unreadable_telemetry(payload: bytes, why: str) -> None:
    with pytest.raises(BatchError, match=why):
        read_telemetry(payload, None)


@pytest.mark.parametrize(
    ("payload", "expected"),
    [
        (b"", {"status": "succeeded"}),
        (b'{"result": {"rate": 5}}', {"status": "succeeded", "result": {"rate": 5}}),
        (b'{"error": "jammed"}', {"status": "failed", "error": "jammed"}),
        (b'{"status": "failed"}', {"status": "failed"}),
    ],
)
def test_results(payload: bytes, expected: dict[str, Any]) -> None:
    assert result_message("c1", payload) == {"type": "result", "id": "c1", **expected}


def test_a_result_must_be_an_object() -> None:
    with pytest.raises(BatchError, match="a result is a JSON object"):
        result_message("c1", b"[1]")


def test_reported() -> None:
    assert reported_message(b'{"rate": 50}', 4) == {
        "type": "reported", "properties": {"rate": 50}, "id": 4,
    }  # fmt: skip


BIG = 2**80


def test_telemetry_keeps_big_integers_exact_for_the_platform_to_reject() -> None:
    # Never rounded to a float: the platform rejects the sample with the one message.
    assert read_telemetry(f'{{"angle": {BIG}}}'.encode(), None).samples == [
        {"values": {"angle": BIG}}
    ]


@pytest.mark.parametrize("seq", [2**63, -(2**63) - 1, BIG])
def test_a_batch_number_beyond_64_bits_is_refused(seq: int) -> None:
    with pytest.raises(BatchError) as err:
        read_telemetry(f'{{"seq": {seq}, "samples": []}}'.encode(), None)
    assert str(err.value) == f"seq: {int64_problem(seq)}"


@pytest.mark.parametrize(
    ("payload", "why"),
    [
        (f'{{"result": {{"count": [1, {BIG}]}}}}', "a result: result.count[1]: "),
        (f'{{"status": "failed", "error": "x", "code": {-BIG}}}', "a result: code: "),
    ],
)
def test_a_result_holding_an_integer_beyond_64_bits_is_refused(payload: str, why: str) -> None:
    with pytest.raises(BatchError) as err:
        result_message("c1", payload.encode())
    assert str(err.value).startswith(why) and "does not fit in 64 bits" in str(err.value)


def test_reported_properties_beyond_64_bits_are_refused_with_their_name() -> None:
    with pytest.raises(BatchError) as err:
        reported_message(f'{{"rate": 50, "count": {BIG}}}'.encode(), 4)
    assert str(err.value) == f"reported properties: count: {int64_problem(BIG)}"
