"""Reading a sample batch from the wire: the batch as a whole, and sample times."""

from __future__ import annotations

from typing import Any

import pytest

from tests.unit._samples import (
    EARLIEST_NS,
    LATEST_NS,
    NOW,
    T2024,
    one,
    read,
    reason,
)
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.samples import (
    MAX_SAMPLES,
    OPEN_SCHEMA,
    BatchError,
    read_batch,
)

# --- the batch as a whole ---------------------------------------------------------------------


def test_a_plain_batch_is_read_in_order() -> None:
    out = read(
        [
            {"time": T2024 * 10**9, "values": {"a": 1, "b": 2.5}},
            {"time": T2024 * 10**9 + 1, "values": {"c": True, "d": "on"}},
        ],
        seq=42,
    )
    assert out.seq == 42
    assert out.stream == "telemetry"
    assert out.times == [T2024 * 10**9, T2024 * 10**9 + 1]
    assert out.values == [{"a": 1, "b": 2.5}, {"c": True, "d": "on"}]
    assert out.rejected == []
    assert (out.server_timed, out.dropped) == (0, 0)


def test_an_empty_sample_list_is_a_valid_batch() -> None:
    out = read([])
    assert out.times == [] and out.rejected == []


@pytest.mark.parametrize("body", [None, [], "batch", 7])
def test_a_batch_must_be_an_object(body: Any) -> None:
    with pytest.raises(BatchError, match="a batch is a JSON object with `seq` and `samples`"):
        read_batch(body, OPEN_SCHEMA, NOW)


@pytest.mark.parametrize("seq", [0, 1, 2**63 - 1])
def test_seq_accepts_0_to_2_63_minus_1(seq: int) -> None:
    assert read([], seq=seq).seq == seq


@pytest.mark.parametrize("seq", [-1, 2**63, True, False, 1.0, "1", None])
def test_seq_outside_the_range_or_not_an_integer_is_refused(seq: Any) -> None:
    with pytest.raises(BatchError, match=r"`seq` must be an integer from 0 to 2\^63-1"):
        read([], seq=seq)


def test_a_batch_without_seq_is_refused() -> None:
    with pytest.raises(BatchError, match="`seq`"):
        read_batch({"samples": []}, OPEN_SCHEMA, NOW)


def test_batch_error_is_an_invalid_input_error() -> None:
    assert issubclass(BatchError, InvalidInputError)
    assert issubclass(BatchError, ValueError)


@pytest.mark.parametrize("stream", ["telemetry", "a", "imu-2_raw", "x" * 64, "a0"])
def test_valid_stream_names(stream: str) -> None:
    assert read([], stream=stream).stream == stream


@pytest.mark.parametrize("stream", ["", "Telemetry", "1abc", "_a", "-a", "a.b", "a b", "x" * 65, 5])
def test_invalid_stream_names_are_refused(stream: Any) -> None:
    with pytest.raises(BatchError, match=r"`stream` must match \^\[a-z\]"):
        read([], stream=stream)


@pytest.mark.parametrize("unit", ["sec", "S", "", None, 1])
def test_an_unknown_time_unit_is_refused(unit: Any) -> None:
    with pytest.raises(BatchError, match="`time_unit` must be one of ns, us, ms, s"):
        read([], time_unit=unit)


@pytest.mark.parametrize("samples", [None, {}, "[]", 3])
def test_samples_must_be_a_list(samples: Any) -> None:
    with pytest.raises(BatchError, match="`samples` must be a list"):
        read_batch({"seq": 1, "samples": samples}, OPEN_SCHEMA, NOW)


def test_a_batch_without_samples_is_refused() -> None:
    with pytest.raises(BatchError, match="`samples` must be a list"):
        read_batch({"seq": 1}, OPEN_SCHEMA, NOW)


def test_too_many_samples_refuse_the_batch_and_say_how_many() -> None:
    sample = {"values": {"a": 1}}
    assert len(read([sample] * MAX_SAMPLES).times) == MAX_SAMPLES
    with pytest.raises(BatchError) as err:
        read([sample] * (MAX_SAMPLES + 1))
    assert str(err.value) == f"a batch holds at most {MAX_SAMPLES} samples, this one 100001"


# --- times ------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("unit", "time"),
    [
        ("ns", T2024 * 10**9),
        ("us", T2024 * 10**6),
        ("ms", T2024 * 10**3),
        ("s", T2024),
    ],
)
def test_integer_times_are_scaled_to_ns(unit: str, time: int) -> None:
    out = one({"time": time, "values": {"a": 1}}, time_unit=unit)
    assert out.times == [T2024 * 10**9]


def test_the_default_time_unit_is_ns() -> None:
    assert one({"time": T2024 * 10**9, "values": {"a": 1}}).times == [T2024 * 10**9]


def test_fractional_times_are_converted_to_integer_ns() -> None:
    # a float near 1.7e18 ns has a resolution of 256 ns, so compare to within 1 us
    out = one({"time": T2024 + 0.25, "values": {"a": 1}}, time_unit="s")
    assert type(out.times[0]) is int
    assert out.times[0] == pytest.approx(T2024 * 10**9 + 250_000_000, abs=1_000)
    out = one({"time": T2024 * 1000 + 0.5, "values": {"a": 1}}, time_unit="ms")
    assert out.times[0] == pytest.approx(T2024 * 10**9 + 500_000, abs=1_000)
    out = one({"time": float(T2024 * 10**9), "values": {"a": 1}})
    assert out.times == [T2024 * 10**9]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("2024-01-01T00:00:00Z", T2024 * 10**9),
        ("2024-01-01T00:00:00+00:00", T2024 * 10**9),
        ("2024-01-01T01:00:00+01:00", T2024 * 10**9),
        ("2023-12-31T19:30:00-04:30", T2024 * 10**9),
        ("2024-01-01T00:00:00.123456Z", T2024 * 10**9 + 123_456_000),
        ("2024-01-01T00:00:00.5Z", T2024 * 10**9 + 500_000_000),
        ("2024-01-01 00:00:00.000001Z", T2024 * 10**9 + 1_000),
    ],
)
def test_iso_times_with_a_zone(text: str, expected: int) -> None:
    out = one({"time": text, "values": {"a": 1}})
    assert out.times == [expected]
    assert out.server_timed == 0


def test_iso_times_ignore_the_time_unit() -> None:
    out = one({"time": "2024-01-01T00:00:00Z", "values": {"a": 1}}, time_unit="s")
    assert out.times == [T2024 * 10**9]


def test_iso_times_keep_exact_microseconds_up_to_2200() -> None:
    out = one({"time": "2108-10-15T17:26:28.508021Z", "values": {"a": 1}})
    assert out.times == [4_379_765_188_508_021_000]


@pytest.mark.parametrize("text", ["2024-01-01T00:00:00", "2024-01-01", "2024-01-01T00:00:00.5"])
def test_iso_times_without_a_zone_are_rejected(text: str) -> None:
    assert reason({"time": text, "values": {"a": 1}}) == (
        f"`time` {text!r} has no time zone (add Z for UTC)"
    )


@pytest.mark.parametrize("text", ["garbage", "", "yesterday", "2024-13-01T00:00:00Z"])
def test_unreadable_time_strings_are_rejected(text: str) -> None:
    assert reason({"time": text, "values": {"a": 1}}) == f"`time` {text!r} is not an ISO 8601 time"


@pytest.mark.parametrize("raw", [True, [1], {"t": 1}, float("nan"), float("inf")])
def test_times_of_other_types_are_rejected(raw: Any) -> None:
    assert reason({"time": raw, "values": {"a": 1}}) == (
        "`time` must be an integer, a number or an ISO 8601 string"
    )


@pytest.mark.parametrize("sample", [{"values": {"a": 1}}, {"time": None, "values": {"a": 1}}])
def test_a_missing_time_takes_the_server_clock(sample: dict[str, Any]) -> None:
    out = one(sample)
    assert out.times == [NOW]
    assert out.server_timed == 1


def test_server_timed_counts_only_samples_without_time() -> None:
    out = read(
        [
            {"values": {"a": 1}},
            {"time": T2024 * 10**9, "values": {"a": 2}},
            {"values": {"a": 3}},
            {"values": {}},  # rejected: not counted
        ]
    )
    assert out.times == [NOW, T2024 * 10**9, NOW]
    assert out.server_timed == 2


@pytest.mark.parametrize(
    ("time", "unit", "expected"),
    [
        (EARLIEST_NS, "ns", EARLIEST_NS),
        (LATEST_NS, "ns", LATEST_NS),
        (631_152_000, "s", EARLIEST_NS),
        (7_258_118_400_000, "ms", LATEST_NS),
        ("1990-01-01T00:00:00Z", "ns", EARLIEST_NS),
        ("2200-01-01T00:00:00Z", "ns", LATEST_NS),
    ],
)
def test_times_at_the_ends_of_1990_to_2200_are_kept(time: Any, unit: str, expected: int) -> None:
    assert one({"time": time, "values": {"a": 1}}, time_unit=unit).times == [expected]


@pytest.mark.parametrize(
    ("time", "unit"),
    [
        (EARLIEST_NS - 1, "ns"),
        (LATEST_NS + 1, "ns"),
        (T2024, "ns"),  # seconds sent as ns: 1970
        (T2024 * 1000, "s"),  # ms sent as s: far future
        (0, "ns"),
        (-1, "s"),
        ("1989-12-31T23:59:59Z", "ns"),
        ("2200-01-01T00:00:01Z", "ns"),
    ],
)
def test_times_outside_1990_to_2200_are_rejected_with_a_unit_hint(time: Any, unit: str) -> None:
    assert reason({"time": time, "values": {"a": 1}}, time_unit=unit) == (
        f"`time` {time!r} is outside 1990..2200 (is `time_unit` right?)"
    )
