"""OPC UA values and the platform's: what a notification becomes (a value and its time, or the
reason it is not stored), what a command argument becomes for a node's data type, and the
batches the notifications are gathered into."""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

from asyncua import ua

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.jsontext import int64_problem
from twinlink.domain.samples import MAX_STRING, Value

_EPOCH = datetime(1970, 1, 1, tzinfo=UTC)
# Earlier source times are a device clock never set (OPC UA's null time is 1601): not data.
_EARLIEST = datetime(1990, 1, 1, tzinfo=UTC)
_INT64 = 1 << 63
_INT_RANGES = {
    ua.VariantType.SByte: (-(1 << 7), 1 << 7),
    ua.VariantType.Byte: (0, 1 << 8),
    ua.VariantType.Int16: (-(1 << 15), 1 << 15),
    ua.VariantType.UInt16: (0, 1 << 16),
    ua.VariantType.Int32: (-(1 << 31), 1 << 31),
    ua.VariantType.UInt32: (0, 1 << 32),
    ua.VariantType.Int64: (-_INT64, _INT64),
    ua.VariantType.UInt64: (0, 1 << 64),
}
_FLOATS = (ua.VariantType.Float, ua.VariantType.Double)


class ValueRefused(TwinlinkError, ValueError):
    """A value that cannot cross between OPC UA and the platform; the text says why."""


@dataclass(frozen=True, slots=True)
class Reading:
    """One notification, read: a value and its time (ns), or the reason it is not one."""

    time_ns: int
    value: Value | None = None
    error_kind: str = ""
    error: str = ""


def read_data_value(data: ua.DataValue | None, arrival_ns: int) -> Reading:
    """A notification's value and time: the source timestamp, else the server's, else the
    arrival. A Bad status code or a value of no platform type gives an error instead."""
    if data is None:
        return Reading(arrival_ns, error_kind="bad_status", error="a notification without value")
    time_ns = _time_ns(data.SourceTimestamp) or _time_ns(data.ServerTimestamp) or arrival_ns
    code = data.StatusCode
    if code is not None and code.is_bad():
        return Reading(time_ns, error_kind="bad_status", error=code.name)
    raw = data.Value.Value if data.Value is not None else None
    try:
        return Reading(time_ns, platform_value(raw))
    except ValueRefused as err:
        return Reading(time_ns, error_kind="unsupported_value", error=str(err))


def _time_ns(stamp: datetime | None) -> int | None:
    if stamp is None:
        return None
    if stamp.tzinfo is None:
        stamp = stamp.replace(tzinfo=UTC)
    if stamp < _EARLIEST:
        return None
    return (stamp - _EPOCH) // timedelta(microseconds=1) * 1000


def platform_value(raw: Any) -> Value:
    """An OPC UA value as a platform value (number, bool or string)."""
    if isinstance(raw, bool):
        return raw
    if isinstance(raw, int):  # every integer type, enumerations too
        if not -_INT64 <= raw < _INT64:
            raise ValueRefused(int64_problem(raw))
        return int(raw)
    if isinstance(raw, float):
        if not math.isfinite(raw):
            raise ValueRefused(f"{raw} is not a finite number")
        return float(raw)
    if isinstance(raw, ua.LocalizedText):
        raw = raw.Text or ""
    if isinstance(raw, str):
        if len(raw) > MAX_STRING:
            raise ValueRefused(f"a string of {len(raw)} characters (at most {MAX_STRING})")
        return str(raw)
    if isinstance(raw, datetime):
        return raw.isoformat().replace("+00:00", "Z")
    if raw is None:
        raise ValueRefused("the value is empty (null)")
    what = "an array" if isinstance(raw, list | tuple) else f"a {type(raw).__name__}"
    raise ValueRefused(f"{what} is not a number, bool or string")


def variant_for(value: Any, vtype: ua.VariantType) -> ua.Variant:
    """A command argument as a Variant of the node's data type; refuses what does not fit."""
    if vtype == ua.VariantType.Variant:  # BaseDataType, Number: the value says its type
        vtype = _natural_type(value)
    if vtype in _FLOATS:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ValueRefused(f"{_show(value)} is not a number ({vtype.name} expected)")
        return ua.Variant(float(value), vtype)
    if vtype in _INT_RANGES:
        low, high = _INT_RANGES[vtype]
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueRefused(f"{_show(value)} is not an integer ({vtype.name} expected)")
        if not low <= value < high:
            raise ValueRefused(f"{value} is outside {vtype.name} ({low} to {high - 1})")
        return ua.Variant(value, vtype)
    return _other_variant(value, vtype)


def _other_variant(value: Any, vtype: ua.VariantType) -> ua.Variant:
    if vtype == ua.VariantType.Boolean and isinstance(value, bool):
        return ua.Variant(value, vtype)
    if vtype == ua.VariantType.String and isinstance(value, str):
        return ua.Variant(value, vtype)
    if vtype == ua.VariantType.LocalizedText and isinstance(value, str):
        return ua.Variant(ua.LocalizedText(value), vtype)
    if vtype == ua.VariantType.DateTime and isinstance(value, str):
        try:
            stamp = datetime.fromisoformat(value.replace("Z", "+00:00"))
        except ValueError as err:
            raise ValueRefused(f"{_show(value)} is not an ISO 8601 time") from err
        return ua.Variant(stamp, vtype)
    if vtype in (ua.VariantType.Boolean, ua.VariantType.String, ua.VariantType.LocalizedText):
        expected = "a bool" if vtype == ua.VariantType.Boolean else "a string"
        raise ValueRefused(f"{_show(value)} is not {expected} ({vtype.name} expected)")
    if vtype == ua.VariantType.DateTime:
        raise ValueRefused(f"{_show(value)} is not an ISO 8601 time (DateTime expected)")
    raise ValueRefused(f"writing the data type {vtype.name} is not supported")


def _natural_type(value: Any) -> ua.VariantType:
    if isinstance(value, bool):
        return ua.VariantType.Boolean
    if isinstance(value, int):
        return ua.VariantType.Int64
    if isinstance(value, float):
        return ua.VariantType.Double
    if isinstance(value, str):
        return ua.VariantType.String
    raise ValueRefused(f"{_show(value)} is not a number, bool or string")


def json_value(raw: Any) -> Any:
    """A method's output argument for a command result (JSON): the value, or its text."""
    if isinstance(raw, list | tuple):
        return [json_value(item) for item in raw]
    try:
        return platform_value(raw)
    except ValueRefused:
        return None if raw is None else str(raw)


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


class SampleBatcher:
    """Notifications gathered into the samples of one batch: values with the same time share a
    sample (a server publishes a scan of many nodes with one timestamp), in arrival order."""

    def __init__(self) -> None:
        self.samples: list[dict[str, Any]] = []
        self._by_time: dict[int, dict[str, Value]] = {}
        self.has_samples = asyncio.Event()

    def __len__(self) -> int:
        return len(self.samples)

    def add(self, time_ns: int, signal: str, value: Value) -> None:
        values = self._by_time.get(time_ns)
        if values is None or signal in values:  # a second value of one signal at one time
            values = self._by_time[time_ns] = {}
            self.samples.append({"time": time_ns, "values": values})
            self.has_samples.set()
        values[signal] = value

    def take(self) -> list[dict[str, Any]]:
        samples, self.samples = self.samples, []
        self._by_time = {}
        self.has_samples.clear()
        return samples
