"""The UDP datasource's configuration: what works is accepted and survives a round trip
through storage; what cannot work is refused with the reason."""

from __future__ import annotations

from typing import Any

import pytest
from pydantic import ValidationError

from twinlink.connectors.udp.config import UdpConfig, value_codes


def config(**fields: Any) -> UdpConfig:
    return UdpConfig.model_validate({"port": 5005, **fields})


def refused(**fields: Any) -> str:
    with pytest.raises(ValidationError) as caught:
        config(**fields)
    return str(caught.value)


def test_the_defaults_listen_on_loopback_for_loopback_senders() -> None:
    c = config(byte_format="<d", channels=["x"])
    assert (c.host, c.format, c.time_unit, c.time_origin, c.stream) == (
        "127.0.0.1", "struct", "s", "epoch", "telemetry"
    )  # fmt: skip
    assert c.allowed_senders == ["127.0.0.1", "::1"] and c.nan == "reject"
    assert (c.batch_window_ms, c.batch_max_samples) == (5.0, 1000)


def test_a_config_survives_storage_as_json() -> None:
    c = config(
        format="catman", channels=["time", None, "force"], single=True, time_channel="time",
        time_origin="start", allowed_senders=["10.0.0.0/8"],
    )  # fmt: skip
    assert UdpConfig.model_validate(c.model_dump(mode="json")) == c
    assert c.record_format() == "<HHIfff"


def test_value_codes_expand_counts_and_skip_pad_bytes() -> None:
    assert value_codes("<d2f3x?") == ["d", "f", "f", "?"]
    assert value_codes("! Q h") == ["Q", "h"]


@pytest.mark.parametrize(
    ("fields", "reason"),
    [
        ({"byte_format": "dff", "channels": ["a", "b", "c"]}, "start with the byte order"),
        ({"byte_format": "@dff", "channels": ["a", "b", "c"]}, "start with the byte order"),
        ({"byte_format": "<d4s", "channels": ["a", "b"]}, "type codes from"),
        ({"byte_format": "<dff", "channels": ["a", "b"]}, "holds 3 values, channels names 2"),
        ({"byte_format": "<9000d", "channels": ["a"]}, "larger than a UDP datagram"),
        ({"channels": ["a"]}, "needs byte_format"),
        ({"byte_format": "<d", "channels": ["1x"]}, "must match"),
        ({"byte_format": "<dd", "channels": ["a", "a"]}, "appear once"),
        ({"byte_format": "<dd", "channels": ["t", "a"], "time_channel": "z"}, "not one of"),
        ({"byte_format": "<d?", "channels": ["a", "t"], "time_channel": "t"}, "is a bool"),
        ({"byte_format": "<dd", "channels": ["t", None], "time_channel": "t"}, "besides the time"),
        ({"format": "catman"}, "catman needs channels"),
        ({"format": "catman", "channels": ["a"], "byte_format": "<d"}, "for format struct only"),
        ({"format": "json", "single": True}, "for format catman only"),
        ({"format": "json", "channels": ["a", None]}, "no null"),
        ({"format": "json", "host": "localhost"}, "not an IP address"),
        ({"format": "json", "allowed_senders": ["10.0.0.300"]}, "not an IP address or network"),
        ({"format": "json", "allowed_senders": []}, "at least 1"),
        ({"format": "json", "stream": "Bad Stream"}, "a stream name matches"),
        ({"format": "json", "port": 70000}, "less than or equal to 65535"),
        ({"format": "json", "batch_max_samples": 0}, "greater than or equal to 1"),
        ({"format": "json", "colour": "blue"}, "Extra inputs are not permitted"),
        ({"format": "csv"}, "'struct', 'catman' or 'json'"),
    ],
)
def test_a_config_that_cannot_work_is_refused_with_the_reason(
    fields: dict[str, Any], reason: str
) -> None:
    assert reason in refused(**fields)


def test_the_port_is_required() -> None:
    with pytest.raises(ValidationError, match="port"):
        UdpConfig.model_validate({"format": "json"})
