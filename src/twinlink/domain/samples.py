"""Samples and batches: the unit of telemetry, and how a batch from the wire is read.

A batch is judged sample by sample: a bad sample is rejected with its reason and the rest are
kept. Only a batch that cannot be read at all (no `seq`, `samples` not a list, too many) is
refused whole, by raising `BatchError`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from datetime import UTC, datetime, timedelta
from typing import Any, Literal

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.jsontext import first_big_int, int64_problem

Value = float | int | bool | str

SIGNAL_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.:-]{0,127}$")
STREAM_NAME = re.compile(r"^[a-z][a-z0-9_-]{0,63}$")
MAX_SAMPLES = 100_000
MAX_STRING = 1024
MAX_REPORTED_REJECTIONS = 100
_EPOCH = datetime(1970, 1, 1, tzinfo=UTC)
_SEQ_LIMIT = 1 << 63
_INT_LIMIT = 1 << 63
_UNIT_NS = {"ns": 1, "us": 1_000, "ms": 1_000_000, "s": 1_000_000_000}
# Device clocks earlier than 1990 or later than 2200 are typos of the time unit, not data.
_EARLIEST_NS = 631_152_000 * 10**9
_LATEST_NS = 7_258_118_400 * 10**9


class BatchError(InvalidInputError):
    """The batch as a whole cannot be read; nothing of it is stored."""


@dataclass(slots=True)
class SampleBatch:
    """Samples of one stream of one twin, in arrival order. Times are ns since the epoch."""

    twin_id: int
    twin: str
    stream: str
    times: list[int]
    values: list[dict[str, Value]]
    received_ns: int
    source: str = ""
    seq: int | None = None

    def __len__(self) -> int:
        return len(self.times)


@dataclass(slots=True)
class Rejection:
    index: int
    reason: str


@dataclass(slots=True)
class ReadBatch:
    """A batch as read from the wire: what is kept, what was rejected and why."""

    seq: int
    stream: str
    times: list[int] = field(default_factory=list)
    values: list[dict[str, Value]] = field(default_factory=list)
    rejected: list[Rejection] = field(default_factory=list)
    server_timed: int = 0
    dropped: int = 0


@dataclass(slots=True, frozen=True)
class SignalRule:
    type: Literal["number", "integer", "bool", "string"]
    min: float | None
    max: float | None


@dataclass(slots=True, frozen=True)
class Schema:
    """What a twin's `interface` allows; `Schema.OPEN` when the twin declares none."""

    signals: dict[str, SignalRule]
    unknown_signals: Literal["accept", "drop", "reject"] = "accept"
    out_of_range: Literal["accept", "reject"] = "reject"

    @property
    def is_open(self) -> bool:
        return not self.signals and self.unknown_signals == "accept"


OPEN_SCHEMA = Schema(signals={})


def schema_from_interface(interface: dict[str, Any] | None) -> Schema:
    """Build the checking rules from a merged DT document's `interface` mapping."""
    if not interface:
        return OPEN_SCHEMA
    rules = {}
    for signal in interface.get("signals") or []:
        if isinstance(signal, dict) and isinstance(signal.get("name"), str):
            rules[signal["name"]] = SignalRule(
                type=signal.get("type", "number"), min=signal.get("min"), max=signal.get("max")
            )
    unknown = interface.get("unknown_signals", "accept")
    out_of_range = interface.get("out_of_range", "reject")
    return Schema(rules, unknown, out_of_range)


def big_int_outside_samples(message: dict[str, Any]) -> str | None:
    """Why a device message (read with `jsontext.loads`) is refused for an integer outside
    64 bits anywhere but in its `samples` (each sample is judged on its own by `read_batch`,
    which already looks at every value), or None. The message names the place."""
    for key, value in message.items():
        kind = type(value)
        if kind is int:  # `seq`, an `id`: inline, this runs for every message of a device
            if not -_INT_LIMIT <= value < _INT_LIMIT:
                return f"{key}: {int64_problem(value)}"
        elif (kind is dict or kind is list) and key != "samples":
            found = first_big_int(value, str(key))
            if found is not None:
                return f"{found[0]}: {int64_problem(found[1])}"
    return None


def read_batch(body: Any, schema: Schema, now_ns: int) -> ReadBatch:
    """Read one batch (already parsed JSON). Raises `BatchError` when it cannot be read."""
    if not isinstance(body, dict):
        raise BatchError("a batch is a JSON object with `seq` and `samples`")
    seq = body.get("seq")
    if type(seq) is not int or not 0 <= seq < _SEQ_LIMIT:
        raise BatchError("`seq` must be an integer from 0 to 2^63-1")
    stream = body.get("stream", "telemetry")
    if not isinstance(stream, str) or not STREAM_NAME.match(stream):
        raise BatchError(f"`stream` must match {STREAM_NAME.pattern}")
    unit = body.get("time_unit", "ns")
    if unit not in _UNIT_NS:
        raise BatchError("`time_unit` must be one of ns, us, ms, s")
    samples = body.get("samples")
    if not isinstance(samples, list):
        raise BatchError("`samples` must be a list")
    if len(samples) > MAX_SAMPLES:
        raise BatchError(f"a batch holds at most {MAX_SAMPLES} samples, this one {len(samples)}")
    out = ReadBatch(seq=seq, stream=stream)
    scale = _UNIT_NS[unit]
    for index, sample in enumerate(samples):
        try:
            time_ns, values, dropped = _read_sample(sample, schema, scale, now_ns)
        except ValueError as err:
            out.rejected.append(Rejection(index, str(err)))
            continue
        if time_ns is None:
            time_ns = now_ns
            out.server_timed += 1
        out.times.append(time_ns)
        out.values.append(values)
        out.dropped += dropped
    return out


def _read_sample(
    sample: Any, schema: Schema, scale: int, now_ns: int
) -> tuple[int | None, dict[str, Value], int]:
    if not isinstance(sample, dict):
        raise ValueError("a sample is an object with `values` and an optional `time`")
    values = sample.get("values")
    if not isinstance(values, dict) or not values:
        raise ValueError("`values` must be an object with at least one signal")
    time_ns = _read_time(sample.get("time"), scale)
    if schema.is_open:
        for name, value in values.items():
            # The common case inline (a known name and a finite float): this runs per value.
            if type(value) is not float or value - value != 0.0 or name not in _GOOD_NAMES:
                _check_plain(name, value)
        return time_ns, values, 0
    return time_ns, *_check_schema(values, schema)


def _read_time(raw: Any, scale: int) -> int | None:
    if type(raw) is int and _EARLIEST_NS <= raw * scale <= _LATEST_NS:  # the common case
        return raw * scale
    if raw is None:
        return None
    if type(raw) is int:
        time_ns = raw * scale
    elif isinstance(raw, float) and math.isfinite(raw):
        time_ns = round(raw * scale)
    elif isinstance(raw, str):
        try:
            parsed = datetime.fromisoformat(raw.replace("Z", "+00:00"))
        except ValueError as err:
            raise ValueError(f"`time` {_show(raw)} is not an ISO 8601 time") from err
        if parsed.tzinfo is None:
            raise ValueError(f"`time` {_show(raw)} has no time zone (add Z for UTC)")
        # Integer arithmetic: a float timestamp loses microseconds after 2106.
        time_ns = (parsed - _EPOCH) // timedelta(microseconds=1) * 1000
    else:
        raise ValueError("`time` must be an integer, a number or an ISO 8601 string")
    if not _EARLIEST_NS <= time_ns <= _LATEST_NS:
        raise ValueError(f"`time` {_show(raw)} is outside 1990..2200 (is `time_unit` right?)")
    return time_ns


# Signal names already found valid: a set lookup instead of a regex per value on the hot
# path. Bounded, so names from a misbehaving device cannot grow it without limit.
_GOOD_NAMES: set[str] = set()
_GOOD_NAMES_MAX = 100_000


def _check_name(name: Any) -> None:
    if name in _GOOD_NAMES:
        return
    if not isinstance(name, str) or not SIGNAL_NAME.match(name):
        raise ValueError(f"signal name {name!r} must match {SIGNAL_NAME.pattern}")
    if len(_GOOD_NAMES) >= _GOOD_NAMES_MAX:
        _GOOD_NAMES.clear()
    _GOOD_NAMES.add(name)


def _check_plain(name: Any, value: Any) -> None:
    _check_name(name)
    kind = type(value)
    if kind is float:
        if not math.isfinite(value):
            raise ValueError(f"{name}: {value} is not a finite number")
    elif kind is int:
        if not -_INT_LIMIT <= value < _INT_LIMIT:
            raise ValueError(f"{name}: {int64_problem(value)}")
    elif kind is str:
        if len(value) > MAX_STRING:
            raise ValueError(f"{name}: a string value holds at most {MAX_STRING} characters")
    elif kind is not bool:
        raise ValueError(f"{name}: {_show(value)} is not a number, bool or string")


def _check_schema(values: dict[str, Any], schema: Schema) -> tuple[dict[str, Value], int]:
    kept: dict[str, Value] = {}
    dropped = 0
    for name, value in values.items():
        _check_plain(name, value)
        rule = schema.signals.get(name)
        if rule is None:
            if schema.unknown_signals == "reject":
                raise ValueError(f"{name}: not a signal of this twin's interface")
            if schema.unknown_signals == "drop":
                dropped += 1
                continue
        else:
            _check_rule(name, value, rule, schema.out_of_range == "reject")
        kept[name] = value
    if not kept:
        raise ValueError("no signal of this twin's interface is in `values`")
    return kept, dropped


def _check_rule(name: str, value: Value, rule: SignalRule, range_checked: bool) -> None:
    kind = type(value)
    if rule.type == "number" and kind not in (int, float):
        raise ValueError(f"{name}: {_show(value)} is not a number")
    if rule.type == "integer" and kind is not int:
        raise ValueError(f"{name}: {_show(value)} is not an integer")
    if rule.type == "bool" and kind is not bool:
        raise ValueError(f"{name}: {_show(value)} is not a bool")
    if rule.type == "string" and kind is not str:
        raise ValueError(f"{name}: {_show(value)} is not a string")
    if range_checked and kind in (int, float):
        assert isinstance(value, int | float)
        if rule.min is not None and value < rule.min:
            raise ValueError(f"{name}: {value} is below the minimum {rule.min}")
        if rule.max is not None and value > rule.max:
            raise ValueError(f"{name}: {value} is above the maximum {rule.max}")


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
