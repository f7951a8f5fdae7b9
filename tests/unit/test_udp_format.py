"""Datagrams to samples: struct formats with channels and a time channel, the catman preset
in double and single precision, several records per datagram, JSON in both forms, and each
kind of malformed input giving its kind and reason."""

from __future__ import annotations

import math
import struct
from collections.abc import Sequence

import orjson
import pytest

from twinlink.connectors.udp.format import (
    CatmanDecoder,
    Clock,
    DecodeError,
    JsonDecoder,
    StructDecoder,
)

NOW = 1_750_000_000_000_000_000  # an arrival time, ns
T0 = 1_750_000_000.25  # a device time, s since the epoch
S = 1_000_000_000


class Reports(list[tuple[str, str]]):
    def __call__(self, kind: str, text: str) -> None:
        self.append((kind, text))

    def kinds(self) -> list[str]:
        return [kind for kind, _ in self]


def clock(unit: str = "s", origin: str = "epoch") -> Clock:
    return Clock(unit, origin)


def decode_error(decoder: StructDecoder | JsonDecoder, data: bytes) -> DecodeError:
    with pytest.raises(DecodeError) as caught:
        decoder.decode(data, NOW)
    return caught.value


# -- struct ---------------------------------------------------------------------------------


def test_a_struct_record_is_one_sample_named_by_its_channels() -> None:
    decoder = StructDecoder("<dff", ["t", "force", "angle"], "t", clock())
    [sample] = decoder.decode(struct.pack("<dff", T0, 2.5, 0.25), NOW)
    assert sample == {"time": round(T0 * S), "values": {"force": 2.5, "angle": 0.25}}


def test_records_back_to_back_are_several_samples() -> None:
    decoder = StructDecoder(">Qhx?", ["t", "level", "on"], "t", clock("ns"))
    data = b"".join(struct.pack(">Qhx?", NOW + i, -i, i % 2 == 0) for i in range(4))
    samples = decoder.decode(data, NOW)
    assert [s["time"] for s in samples] == [NOW, NOW + 1, NOW + 2, NOW + 3]
    assert [s["values"] for s in samples][1] == {"level": -1, "on": False}


def test_a_null_channel_is_left_out_and_one_value_works() -> None:
    decoder = StructDecoder("<ii", [None, "x"], None, clock())
    assert decoder.decode(struct.pack("<ii", 7, 8), NOW) == [{"time": NOW, "values": {"x": 8}}]


def test_without_a_time_channel_every_record_gets_the_arrival_time() -> None:
    decoder = StructDecoder("<d", ["x"], None, clock())
    samples = decoder.decode(struct.pack("<dd", 1.0, 2.0), NOW)
    assert [s["time"] for s in samples] == [NOW, NOW]


@pytest.mark.parametrize(
    ("unit", "raw", "expected"),
    [("s", 1_750_000_000, 1_750_000_000 * S), ("ms", 1_750_000_000_123, 1_750_000_000_123_000_000),
     ("us", 1_750_000_000_000_001, 1_750_000_000_000_001_000), ("ns", NOW, NOW)],
)  # fmt: skip
def test_the_time_unit_scales_an_integer_time_exactly(unit: str, raw: int, expected: int) -> None:
    decoder = StructDecoder("<qd", ["t", "x"], "t", clock(unit))
    assert decoder.decode(struct.pack("<qd", raw, 1.0), NOW)[0]["time"] == expected


def test_a_relative_time_is_anchored_at_the_first_datagram_s_arrival() -> None:
    decoder = StructDecoder("<dd", ["t", "x"], "t", clock("s", "start"))
    first = decoder.decode(struct.pack("<dddd", 12.0, 1.0, 12.5, 2.0), NOW)
    later = decoder.decode(struct.pack("<dd", 13.0, 3.0), NOW + 7 * S)  # late arrival: ignored
    assert [s["time"] for s in first + later] == [NOW, NOW + S // 2, NOW + S]


def test_a_relative_time_going_back_is_a_restart_anchored_anew() -> None:
    decoder = StructDecoder("<dd", ["t", "x"], "t", clock("s", "start"))
    decoder.decode(struct.pack("<dd", 100.0, 1.0), NOW)
    [restarted] = decoder.decode(struct.pack("<dd", 0.0, 1.0), NOW + 5 * S)
    assert restarted["time"] == NOW + 5 * S
    decoder.reset()  # a new start anchors again too
    assert decoder.decode(struct.pack("<dd", 50.0, 1.0), NOW)[0]["time"] == NOW


def test_a_relative_clock_read_as_epoch_is_counted_with_a_hint() -> None:
    reports = Reports()
    decoder = StructDecoder("<dd", ["t", "x"], "t", clock(), report=reports)
    data = struct.pack("<dddd", 12.0, 1.0, T0, 2.0)
    assert [s["values"]["x"] for s in decoder.decode(data, NOW)] == [2.0]
    [(kind, text)] = reports
    assert kind == "bad_time" and "time_origin: start" in text


def test_a_nan_time_is_a_bad_time() -> None:
    reports = Reports()
    decoder = StructDecoder("<dd", ["t", "x"], "t", clock(), report=reports)
    assert decoder.decode(struct.pack("<dd", math.nan, 1.0), NOW) == []
    assert reports.kinds() == ["bad_time"] and "not a finite number" in reports[0][1]


def test_a_nan_value_rejects_its_row_and_the_other_rows_stay() -> None:
    reports = Reports()
    decoder = StructDecoder("<dd", ["a", "b"], None, clock(), report=reports)
    data = struct.pack("<dddd", 1.0, math.nan, 3.0, 4.0)
    assert [s["values"] for s in decoder.decode(data, NOW)] == [{"a": 3.0, "b": 4.0}]
    assert reports == [("nan", "b is nan (set nan: skip to leave it out)")]


def test_nan_skip_leaves_out_only_the_value_and_an_all_nan_row() -> None:
    reports = Reports()
    decoder = StructDecoder("<dd", ["a", "b"], None, clock(), skip_nan=True, report=reports)
    data = struct.pack("<dddddd", 1.0, math.inf, math.nan, math.nan, 5.0, 6.0)
    assert [s["values"] for s in decoder.decode(data, NOW)] == [{"a": 1.0}, {"a": 5.0, "b": 6.0}]
    assert reports == []


def test_finite_values_whose_sum_overflows_are_kept() -> None:
    decoder = StructDecoder("<dd", ["a", "b"], None, clock())
    [sample] = decoder.decode(struct.pack("<dd", 1.7e308, 1.7e308), NOW)
    assert sample["values"] == {"a": 1.7e308, "b": 1.7e308}


def test_a_short_datagram_is_truncated_and_a_ragged_one_the_wrong_size() -> None:
    decoder = StructDecoder("<dff", ["t", "a", "b"], "t", clock())
    short = decode_error(decoder, b"\x00" * 15)
    assert (short.kind, short.text) == (
        "truncated", "15 bytes, shorter than one record of '<dff' (16 bytes)"
    )  # fmt: skip
    ragged = decode_error(decoder, b"\x00" * 20)
    assert ragged.kind == "wrong_size" and "16-byte records" in ragged.text
    assert decode_error(decoder, b"").kind == "truncated"


# -- catman ---------------------------------------------------------------------------------


def catman_record(counter: int, *values: float, single: bool = False, channels: int = 0) -> bytes:
    code = "f" if single else "d"
    return struct.pack(f"<HHI{len(values)}{code}", 1, channels or len(values), counter, *values)


def test_catman_records_carry_their_header_then_a_double_per_channel() -> None:
    decoder = CatmanDecoder(["time", "strain", "force"], "time", clock("s", "start"))
    data = catman_record(1, 0.0, 1e-4, 2.5) + catman_record(2, 0.01, 2e-4, 2.25)
    samples = decoder.decode(data, NOW)
    assert samples == [
        {"time": NOW, "values": {"strain": 1e-4, "force": 2.5}},
        {"time": NOW + 10_000_000, "values": {"strain": 2e-4, "force": 2.25}},
    ]


def test_catman_single_precision_values_are_four_byte_floats() -> None:
    decoder = CatmanDecoder(["a", "b"], None, clock(), single=True)
    data = catman_record(9, 0.5, -1.25, single=True)
    assert len(data) == 8 + 2 * 4
    assert decoder.decode(data, NOW) == [{"time": NOW, "values": {"a": 0.5, "b": -1.25}}]


def test_catman_header_with_other_channels_names_the_configured_ones() -> None:
    decoder = CatmanDecoder(["a", "b"], None, clock())
    error = decode_error(decoder, catman_record(1, 1.0, 2.0, 3.0))
    assert error.kind == "channel_count"
    assert "header says 3 channels, this connector has 2 (a, b)" in error.text


def test_catman_counter_jumps_are_reported_lost_and_a_restart_is_not() -> None:
    reports = Reports()
    decoder = CatmanDecoder(["a"], None, clock(), report=reports)
    for counter in (1, 2, 5, 6, 0, 1, 0xFFFFFFFF, 0):
        assert len(decoder.decode(catman_record(counter, 1.0), NOW)) == 1
    assert reports == [("lost", "the catman counter went from 2 to 5: 2 lost")]


def test_catman_truncated_header_and_partial_record() -> None:
    decoder = CatmanDecoder(["a", "b"], None, clock())
    assert decode_error(decoder, b"\x01\x00").kind == "truncated"
    assert decode_error(decoder, catman_record(1, 1.0, 2.0)[:-3]).kind == "truncated"
    two = catman_record(1, 1.0, 2.0) + catman_record(2, 1.0, 2.0)[:-1]
    assert decode_error(decoder, two).kind == "wrong_size"


# -- JSON -----------------------------------------------------------------------------------


def json_decoder(
    channels: Sequence[str] = (),
    time_key: str = "time",
    unit: str = "s",
    report: Reports | None = None,
) -> JsonDecoder:
    return JsonDecoder(channels, time_key, clock(unit), report if report is not None else Reports())


def test_a_flat_json_object_is_one_sample_with_its_time() -> None:
    data = orjson.dumps({"force": 2.5, "on": True, "mode": "run", "time": T0})
    [sample] = json_decoder().decode(data, NOW)
    assert sample == {"time": round(T0 * S), "values": {"force": 2.5, "on": True, "mode": "run"}}


def test_a_flat_object_without_time_gets_the_arrival_and_a_custom_time_key() -> None:
    assert json_decoder().decode(b'{"x": 1}', NOW) == [{"time": NOW, "values": {"x": 1}}]
    decoder = json_decoder(time_key="ts", unit="ms")
    [sample] = decoder.decode(b'{"x": 1, "ts": 1750000000123}', NOW)
    assert sample["time"] == 1_750_000_000_123_000_000


def test_the_batch_form_reads_each_sample_and_its_time_unit() -> None:
    data = orjson.dumps(
        {"time_unit": "ns", "samples": [{"time": NOW, "values": {"x": 1}}, {"values": {"x": 2}}]}
    )
    assert json_decoder().decode(data, NOW - 5) == [
        {"time": NOW, "values": {"x": 1}},
        {"time": NOW - 5, "values": {"x": 2}},
    ]


def test_bad_samples_of_a_batch_are_counted_and_the_others_kept() -> None:
    reports = Reports()
    decoder = json_decoder(["x"], report=reports)
    data = orjson.dumps(
        {"samples": [{"values": {"x": 1}}, {"value": 2}, {"time": "soon", "values": {"x": 3}},
                     {"values": {"y": 4}}, {"values": {}}, {"time": 12, "values": {"x": 5}}]}
    )  # fmt: skip
    assert decoder.decode(data, NOW) == [{"time": NOW, "values": {"x": 1}}]
    assert reports.kinds()[:5] == ["bad_sample", "bad_time", "unknown_channel", "bad_sample",
                                   "bad_time"]  # fmt: skip
    assert reports[0][1].startswith("sample 1: ") and "outside 1990..2200" in reports[4][1]


@pytest.mark.parametrize(
    ("data", "kind", "reason"),
    [
        (b"{nope", "bad_json", "not JSON"),
        (b"\xff\xfe", "bad_json", "not JSON"),
        (b'{"x": NaN}', "bad_json", "not JSON"),
        (b"[1, 2]", "bad_json", "one JSON object"),
        (b'{"time": 1750000000}', "bad_sample", "no values"),
        (b'{"x": 1, "z": 2}', "unknown_channel", "z not in channels"),
        (b'{"x": 1, "time": "noon"}', "bad_time", "'noon' is not a number"),
        (b'{"x": 1, "time": 5}', "bad_time", "outside 1990..2200"),
        (b'{"samples": {"x": 1}}', "bad_sample", "must be a list"),
        (b'{"samples": [], "time_unit": "h"}', "bad_sample", "time_unit"),
    ],
)
def test_malformed_json_is_refused_with_its_kind(data: bytes, kind: str, reason: str) -> None:
    error = decode_error(json_decoder(["x", "y"]), data)
    assert error.kind == kind and reason in error.text, error


def test_json_integers_beyond_64_bits_stay_exact_for_the_platform_to_reject() -> None:
    # orjson made 2**80 a float here without a word; the platform now rejects the sample.
    big = 2**80
    assert json_decoder().decode(f'{{"x": {big}}}'.encode(), NOW) == [
        {"time": NOW, "values": {"x": big}}
    ]
    error = decode_error(json_decoder(["x"]), f'{{"x": 1, "time": {big}}}'.encode())
    assert error.kind == "bad_time" and "outside 1990..2200" in error.text
