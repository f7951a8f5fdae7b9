"""One datagram to samples: a Python `struct` byte format with named channels (the Tvilling
digital datasources), its HBM catman preset, and one JSON object per datagram.

A decoder's `decode(data, arrival_ns)` returns the samples (`{"time": ns, "values": {...}}`)
of one datagram. A datagram that cannot be read at all raises `DecodeError` and gives nothing;
a bad row of a good datagram (a NaN, a time out of range) is left out and handed to `report`
with its kind, and the other rows are kept, as the platform judges the samples of a batch.
"""

from __future__ import annotations

import operator
import struct
from collections.abc import Callable, Sequence
from typing import Any

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.jsontext import JsonTextError, loads

Sample = dict[str, Any]
Report = Callable[[str, str], None]

UNIT_NS = {"s": 1_000_000_000, "ms": 1_000_000, "us": 1_000, "ns": 1}
# The platform's window for device clocks (domain.samples): outside it a time is a mistake
# of unit or origin, and saying so here beats a rejected sample without the hint.
EARLIEST_NS = 631_152_000 * 10**9  # 1990
LATEST_NS = 7_258_118_400 * 10**9  # 2200
# A relative time channel going back further than this means the measurement restarted.
RESTART_NS = 1_000_000_000

CATMAN_HEADER = struct.Struct("<HHI")  # id, number of channels, record counter
_COUNTER_SPAN = 1 << 32


class DecodeError(TwinlinkError):
    """The datagram as a whole cannot be read; `kind` is the short name it is counted by."""

    def __init__(self, kind: str, text: str) -> None:
        super().__init__(f"{kind}: {text}")
        self.kind = kind
        self.text = text


def _ignore(kind: str, text: str) -> None:
    return None


class Clock:
    """Device times to ns since the epoch. With `origin="start"` the device counts from the
    start of its measurement: the first time seen is placed at the arrival of its datagram,
    and again whenever the count goes back (the measurement was restarted)."""

    def __init__(self, unit: str, origin: str) -> None:
        self.scale = UNIT_NS[unit]
        self.relative = origin == "start"
        self.offset_ns = 0
        self._last_ns: int | None = None

    def reset(self) -> None:
        self.offset_ns = 0
        self._last_ns = None

    def to_ns(self, raw: Any, arrival_ns: int, scale: int | None = None) -> int:
        """Raises ValueError with the reason when `raw` is not a usable time."""
        kind = type(raw)
        ns: int
        if kind is float:
            scaled = raw * (scale or self.scale)
            if scaled - scaled != 0.0:  # NaN or infinite
                raise ValueError(f"time {raw} is not a finite number")
            ns = round(scaled)
        elif kind is int:
            ns = raw * (scale or self.scale)
        else:
            raise ValueError(f"time {raw!r} is not a number")
        if self.relative:
            if self._last_ns is None or ns < self._last_ns - RESTART_NS:
                self.offset_ns = arrival_ns - ns
            self._last_ns = ns
            ns += self.offset_ns
        if not EARLIEST_NS <= ns <= LATEST_NS:
            raise ValueError(
                f"time {raw!r} is outside 1990..2200: is time_unit right, or does the clock "
                "count from the start of the measurement (time_origin: start)?"
            )
        return ns


# -- struct ---------------------------------------------------------------------------------


class StructDecoder:
    """Records of one `struct.Struct`, back to back: each record is one sample. `channels`
    names each field in order; None leaves a field out; `time_channel` (one of them) is the
    sample's time, else the datagram's arrival time is."""

    def __init__(
        self,
        byte_format: str,
        channels: Sequence[str | None],
        time_channel: str | None,
        clock: Clock,
        skip_nan: bool = False,
        report: Report = _ignore,
    ) -> None:
        self.record = struct.Struct(byte_format)
        self.clock = clock
        self.skip_nan = skip_nan
        self.report = report
        self.time_index = channels.index(time_channel) if time_channel else None
        picked = [i for i, name in enumerate(channels) if name is not None and i != self.time_index]
        self.names: list[str] = [channels[i] or "" for i in picked]
        # itemgetter returns a bare value, not a tuple, for one index.
        self.pick: Callable[[tuple[Any, ...]], tuple[Any, ...]] = (
            operator.itemgetter(*picked) if len(picked) > 1 else lambda row: (row[picked[0]],)
        )

    def reset(self) -> None:
        self.clock.reset()

    def check_size(self, data: bytes) -> None:
        size, length = self.record.size, len(data)
        if length < size:
            raise DecodeError(
                "truncated",
                f"{length} bytes, shorter than one record of {self.record.format!r} ({size} bytes)",
            )
        if length % size:
            raise DecodeError(
                "wrong_size",
                f"{length} bytes is not a whole number of {size}-byte records of "
                f"{self.record.format!r}",
            )

    def decode(self, data: bytes, arrival_ns: int) -> list[Sample]:
        self.check_size(data)
        samples: list[Sample] = []
        names, pick, time_index = self.names, self.pick, self.time_index
        for row in self.record.iter_unpack(data):
            self.check_row(row)
            picked = pick(row)
            total = sum(picked)  # one C-speed pass: a NaN or an infinity makes it non-finite
            values = (
                dict(zip(names, picked, strict=True))
                if total - total == 0.0
                else self.finite_values(picked)
            )
            if values is None:
                continue
            if time_index is None:
                samples.append({"time": arrival_ns, "values": values})
                continue
            try:
                time_ns = self.clock.to_ns(row[time_index], arrival_ns)
            except ValueError as err:
                self.report("bad_time", str(err))
                continue
            samples.append({"time": time_ns, "values": values})
        return samples

    def check_row(self, row: tuple[Any, ...]) -> None:
        """A hook for presets whose records carry a header."""

    def finite_values(self, picked: tuple[Any, ...]) -> dict[str, Any] | None:
        """The values of a row holding a NaN or an infinity (or finite values whose sum
        overflowed): without them under `nan: skip`, None (the row is left out) otherwise."""
        values: dict[str, Any] = {}
        for name, value in zip(self.names, picked, strict=True):
            if type(value) is float and value - value != 0.0:
                if not self.skip_nan:
                    self.report("nan", f"{name} is {value} (set nan: skip to leave it out)")
                    return None
                continue
            values[name] = value
        return values or None


def catman_format(channel_count: int, single: bool) -> str:
    """The record catman sends: its header, then one value per channel (8-byte doubles, or
    4-byte floats in single precision)."""
    return "<HHI" + ("f" if single else "d") * channel_count


class CatmanDecoder(StructDecoder):
    """HBM catman's datagrams: records of a header (`<HHI`: id, number of channels, record
    counter) and one value per channel. The header's channel count is checked against the
    configured channels, and a jump of the counter is reported as lost records."""

    def __init__(
        self,
        channels: Sequence[str | None],
        time_channel: str | None,
        clock: Clock,
        single: bool = False,
        skip_nan: bool = False,
        report: Report = _ignore,
    ) -> None:
        fields: list[str | None] = [None, None, None, *channels]
        fmt = catman_format(len(channels), single)
        super().__init__(fmt, fields, time_channel, clock, skip_nan, report)
        self.channel_count = len(channels)
        self.channel_list = ", ".join(str(name) for name in channels)
        self.counter: int | None = None

    def reset(self) -> None:
        super().reset()
        self.counter = None

    def check_size(self, data: bytes) -> None:
        # The header says how many channels catman sends: a different list of channels is a
        # clearer message than the size it causes.
        if len(data) >= CATMAN_HEADER.size:
            channels = CATMAN_HEADER.unpack_from(data)[1]
            if channels != self.channel_count:
                raise DecodeError(
                    "channel_count",
                    f"the catman header says {channels} channels, this connector has "
                    f"{self.channel_count} ({self.channel_list}): list every channel catman "
                    "sends, in its order",
                )
        super().check_size(data)

    def check_row(self, row: tuple[Any, ...]) -> None:
        counter: int = row[2]
        last, self.counter = self.counter, counter
        if last is None:
            return
        lost = (counter - last - 1) % _COUNTER_SPAN
        # A count going back (catman restarted, or a late datagram) is not a loss.
        if 0 < lost < _COUNTER_SPAN // 2:
            self.report("lost", f"the catman counter went from {last} to {counter}: {lost} lost")


# -- JSON -----------------------------------------------------------------------------------


class JsonDecoder:
    """One JSON object per datagram: flat (`{"signal": value, ..., "time": t}`, the time under
    `time_key`) or the platform's batch form (`{"samples": [{"time": t, "values": {...}}]}`,
    with an optional `time_unit`). `channels`, when given, are the only signals accepted."""

    def __init__(
        self,
        channels: Sequence[str],
        time_key: str,
        clock: Clock,
        report: Report = _ignore,
    ) -> None:
        self.allowed = frozenset(channels) or None
        self.time_key = time_key
        self.clock = clock
        self.report = report

    def reset(self) -> None:
        self.clock.reset()

    def decode(self, data: bytes, arrival_ns: int) -> list[Sample]:
        try:
            body = loads(data)  # integers exact: the platform rejects one beyond 64 bits
        except JsonTextError as err:
            raise DecodeError("bad_json", f"not JSON ({err})") from err
        if not isinstance(body, dict):
            raise DecodeError("bad_json", "a datagram holds one JSON object")
        if "samples" in body:
            return self.batch(body, arrival_ns)
        raw_time = body.pop(self.time_key, None)
        try:
            return [self.sample(body, raw_time, arrival_ns, None)]
        except ValueError as err:
            raise DecodeError("bad_time", str(err)) from err

    def batch(self, body: dict[str, Any], arrival_ns: int) -> list[Sample]:
        rows, unit = body["samples"], body.get("time_unit")
        if not isinstance(rows, list):
            raise DecodeError("bad_sample", "`samples` must be a list")
        if unit is not None and unit not in UNIT_NS:
            raise DecodeError("bad_sample", f"`time_unit` must be one of {', '.join(UNIT_NS)}")
        scale = UNIT_NS[unit] if unit else None
        samples = []
        for index, row in enumerate(rows):
            if not isinstance(row, dict) or not isinstance(row.get("values"), dict):
                self.report("bad_sample", f"sample {index}: an object with `values` is needed")
                continue
            try:
                samples.append(self.sample(row["values"], row.get("time"), arrival_ns, scale))
            except DecodeError as err:
                self.report(err.kind, f"sample {index}: {err.text}")
            except ValueError as err:
                self.report("bad_time", f"sample {index}: {err}")
        return samples

    def sample(
        self, values: dict[str, Any], raw_time: Any, arrival_ns: int, scale: int | None
    ) -> Sample:
        if not values:
            raise DecodeError("bad_sample", "no values, only a time")
        if self.allowed is not None and not self.allowed.issuperset(values):
            unknown = ", ".join(sorted(set(values) - self.allowed))
            raise DecodeError("unknown_channel", f"{unknown} not in channels")
        time_ns = arrival_ns if raw_time is None else self.clock.to_ns(raw_time, arrival_ns, scale)
        return {"time": time_ns, "values": values}
