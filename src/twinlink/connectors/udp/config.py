"""The configuration of a UDP datasource, checked whole when it is created: a format that
cannot work is refused with the reason, never found out datagram by datagram."""

from __future__ import annotations

import ipaddress
import re
import struct
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from twinlink.connectors.udp.format import catman_format
from twinlink.domain.samples import SIGNAL_NAME, STREAM_NAME

MAX_DATAGRAM = 65_507  # the largest UDP payload over IPv4
_CODES = "xbB?hHiIlLqQefd"  # numbers, bools and pad bytes; no strings or native sizes
_BYTE_FORMAT = re.compile(rf"^[<>!=](\s*\d*[{_CODES}])+\s*$")
_FIELD = re.compile(rf"(\d*)([{_CODES}])")


def value_codes(byte_format: str) -> list[str]:
    """The type code of each value a record of `byte_format` unpacks to (pad bytes give
    none): `<d2f` -> ["d", "f", "f"]."""
    codes: list[str] = []
    for count, code in _FIELD.findall(byte_format[1:]):
        if code != "x":
            codes.extend(code * int(count or 1))
    return codes


class UdpConfig(BaseModel):
    """A UDP datasource: the address it listens on, how a datagram maps to samples, and who
    may send."""

    model_config = ConfigDict(extra="forbid")

    host: str = Field(
        "127.0.0.1",
        description="Address to listen on: 127.0.0.1 (this machine only), 0.0.0.0 (every IPv4 "
        "interface), :: (every interface) or the address of one interface.",
    )
    port: int = Field(
        ge=0, le=65535, description="UDP port to listen on (0: any free port, see the status)."
    )
    format: Literal["struct", "catman", "json"] = Field(
        "struct",
        description="struct: records of `byte_format`; catman: HBM catman's records (a `<HHI` "
        "header, then one double per channel); json: one JSON object per datagram.",
    )
    byte_format: str | None = Field(
        None,
        description="struct only: a Python struct format of one record, starting with its "
        "byte order (< little-endian, > or ! big-endian), e.g. `<dff`. A datagram holds one or "
        "more records back to back; each is one sample.",
    )
    channels: list[str | None] = Field(
        default_factory=list,
        description="struct: the name of each value of a record, in order (null leaves one "
        "out). catman: the name of each channel catman sends, in order. json: the signals "
        "accepted (empty: any).",
    )
    single: bool = Field(
        False, description="catman only: the values are single precision (4-byte floats)."
    )
    time_channel: str | None = Field(
        None,
        description="The channel holding each sample's time (json: the key, default `time`). "
        "Without one, a sample's time is the arrival of its datagram.",
    )
    time_unit: Literal["s", "ms", "us", "ns"] = Field(
        "s", description="The unit of the time channel."
    )
    time_origin: Literal["epoch", "start"] = Field(
        "epoch",
        description="epoch: the time channel counts from 1970-01-01 UTC. start: it counts from "
        "the start of the measurement; the first datagram's arrival anchors it.",
    )
    stream: str = Field("telemetry", description="The stream the samples go to.")
    allowed_senders: list[str] = Field(
        default_factory=lambda: ["127.0.0.1", "::1"],
        min_length=1,
        description="IP addresses or networks (CIDR, e.g. 192.168.1.0/24) datagrams are taken "
        "from; the others are refused and counted.",
    )
    nan: Literal["reject", "skip"] = Field(
        "reject",
        description="A NaN or infinite value: reject leaves its whole row out (counted); skip "
        "leaves only that value out.",
    )
    batch_window_ms: float = Field(
        5.0,
        ge=0,
        le=1000,
        description="Samples arriving within this many ms go to the platform as one batch.",
    )
    batch_max_samples: int = Field(
        1000, ge=1, le=100_000, description="A batch is sent at once when it has this many."
    )

    @field_validator("host")
    @classmethod
    def _host(cls, host: str) -> str:
        try:
            ipaddress.ip_address(host)
        except ValueError as err:
            raise ValueError(f"{host!r} is not an IP address (e.g. 127.0.0.1 or 0.0.0.0)") from err
        return host

    @field_validator("stream")
    @classmethod
    def _stream(cls, stream: str) -> str:
        if not STREAM_NAME.match(stream):
            raise ValueError(f"a stream name matches {STREAM_NAME.pattern}")
        return stream

    @field_validator("allowed_senders")
    @classmethod
    def _senders(cls, senders: list[str]) -> list[str]:
        for sender in senders:
            try:
                ipaddress.ip_network(sender, strict=False)
            except ValueError as err:
                raise ValueError(f"{sender!r} is not an IP address or network") from err
        return senders

    @field_validator("channels")
    @classmethod
    def _channels(cls, channels: list[str | None]) -> list[str | None]:
        named = [name for name in channels if name is not None]
        for name in named:
            if not SIGNAL_NAME.match(name):
                raise ValueError(f"channel {name!r} must match {SIGNAL_NAME.pattern}")
        if len(set(named)) != len(named):
            raise ValueError("each channel name may appear once")
        return channels

    @model_validator(mode="after")
    def _format(self) -> UdpConfig:
        if self.format != "struct" and self.byte_format is not None:
            raise ValueError("byte_format is for format struct only")
        if self.format != "catman" and self.single:
            raise ValueError("single is for format catman only")
        if self.format == "json":
            if None in self.channels:
                raise ValueError("json channels are signal names, no null")
            return self
        if self.format == "struct":
            self._check_struct()
        elif not self.channels:
            raise ValueError("catman needs channels: the name of each channel it sends, in order")
        named = [name for name in self.channels if name is not None]
        if self.time_channel is not None and self.time_channel not in named:
            raise ValueError(f"time_channel {self.time_channel!r} is not one of the channels")
        if not [name for name in named if name != self.time_channel]:
            raise ValueError("channels need at least one named value besides the time")
        return self

    def _check_struct(self) -> None:
        fmt = self.byte_format
        if fmt is None:
            raise ValueError("format struct needs byte_format, e.g. `<dff`")
        if not _BYTE_FORMAT.match(fmt):
            raise ValueError(
                f"byte_format {fmt!r}: start with the byte order (<, >, ! or =), then type "
                f"codes from {_CODES} with optional counts, e.g. `<d2f`"
            )
        if struct.calcsize(fmt) > MAX_DATAGRAM:
            raise ValueError(f"byte_format {fmt!r}: a record is larger than a UDP datagram")
        codes = value_codes(fmt)
        if len(codes) != len(self.channels):
            raise ValueError(
                f"byte_format {fmt!r} holds {len(codes)} values, channels names "
                f"{len(self.channels)}: name each (null leaves one out)"
            )
        if self.time_channel in self.channels:
            code = codes[self.channels.index(self.time_channel)]
            if code == "?":
                raise ValueError(f"time_channel {self.time_channel!r} is a bool, not a number")

    def record_format(self) -> str | None:
        """The struct format of one record (struct and catman), None for json."""
        if self.format == "catman":
            return catman_format(len(self.channels), self.single)
        return self.byte_format
