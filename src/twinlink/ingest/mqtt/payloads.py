"""MQTT payloads to the messages of the device protocol (docs/protocol.md), and back.

A telemetry payload is one of (docs/mqtt.md):
- a batch, as on the device WebSocket: `{"seq": 7, "samples": [{"time": ..., "values": {...}}]}`
  (`seq` may be left out: the server numbers it);
- one sample: `{"time": 1732200000123, "values": {"angle": 0.1}}` (`time` optional);
- a list of samples: `[{"time": ..., "values": {...}}, ...]`;
- flat values, one sample at the server's time: `{"angle": 0.1, "load": 2.5}`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import orjson

from twinlink.domain.jsontext import JsonTextError, first_big_int, fits_int64, int64_problem, loads
from twinlink.domain.samples import BatchError


@dataclass(slots=True)
class Telemetry:
    """What a telemetry payload holds: a batch to dispatch (`seq` None: the server numbers
    it)."""

    samples: list[Any]
    stream: str | None
    seq: int | None
    time_unit: str | None

    def message(self, seq: int) -> dict[str, Any]:
        message: dict[str, Any] = {"type": "samples", "seq": seq, "samples": self.samples}
        if self.stream is not None:
            message["stream"] = self.stream
        if self.time_unit is not None:
            message["time_unit"] = self.time_unit
        return message


def parse_json(payload: bytes) -> Any:
    """The payload's JSON, integers exact: samples holding one beyond 64 bits are rejected
    each on its own by the platform, other messages here, whole (`_refuse_big_ints`)."""
    try:
        return loads(payload)
    except JsonTextError as err:
        raise BatchError(f"the payload is not JSON: {err}") from err


def _refuse_big_ints(body: Any, what: str) -> None:
    found = first_big_int(body)
    if found is not None:
        path, number = found
        raise BatchError(f"{what}: {path + ': ' if path else ''}{int64_problem(number)}")


def read_telemetry(payload: bytes, topic_stream: str | None) -> Telemetry:
    """The batch a telemetry payload holds; BatchError when it cannot be read at all (the
    samples themselves are checked by the platform, each on its own)."""
    body = parse_json(payload)
    if isinstance(body, list):
        return Telemetry(body, topic_stream, None, None)
    if not isinstance(body, dict) or not body:
        raise BatchError(
            'a telemetry payload is a JSON object ({"angle": 0.1}, a sample or a batch) '
            "or a list of samples"
        )
    if "samples" in body:
        return _batch(body, topic_stream)
    if isinstance(body.get("values"), dict):
        return Telemetry([body], topic_stream, None, None)
    return Telemetry([{"values": body}], topic_stream, None, None)


def _batch(body: dict[str, Any], topic_stream: str | None) -> Telemetry:
    stream = body.get("stream", topic_stream)
    if topic_stream is not None and stream != topic_stream:
        raise BatchError(f"the topic names stream {topic_stream!r}, the batch {stream!r}")
    seq = body.get("seq")
    if seq is not None and (isinstance(seq, bool) or not isinstance(seq, int)):
        raise BatchError("`seq` must be an integer")
    if seq is not None and not fits_int64(seq):  # it is echoed in acks and errors
        raise BatchError(f"seq: {int64_problem(seq)}")
    samples = body["samples"]
    if not isinstance(samples, list):
        raise BatchError("`samples` must be a list")
    unit = body.get("time_unit")
    return Telemetry(samples, stream, seq, unit if isinstance(unit, str) else None)


def read_object(payload: bytes, what: str) -> dict[str, Any]:
    """A payload that must be a JSON object (empty counts as `{}`)."""
    if not payload.strip():
        return {}
    body = parse_json(payload)
    if not isinstance(body, dict):
        raise BatchError(f"{what} is a JSON object")
    _refuse_big_ints(body, what)
    return body


def result_message(command_id: str, payload: bytes) -> dict[str, Any]:
    """`commands/{id}/result`: `{"status", "result", "error"}`; `status` may be left out
    (failed when there is an `error`, else succeeded), so `-n` (no payload) is a success."""
    body = read_object(payload, "a result")
    status = body.get("status", "failed" if body.get("error") is not None else "succeeded")
    message = {"type": "result", "id": command_id, "status": status}
    for key in ("result", "error"):
        if key in body:
            message[key] = body[key]
    return message


def reported_message(payload: bytes, ref: int) -> dict[str, Any]:
    """`properties/reported`: the properties object itself (`{"sample_rate": 50}`)."""
    return {"type": "reported", "properties": read_object(payload, "reported properties"),
            "id": ref}  # fmt: skip


def dumps(message: dict[str, Any]) -> bytes:
    return orjson.dumps(message)
