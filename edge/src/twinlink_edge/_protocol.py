"""Wire-level helpers: JSON, URLs, sequence numbers, backoff and the ack record.

Nothing here does I/O. See docs/protocol.md in the twinlink repository for the protocol."""

from __future__ import annotations

import json
import math
import random
import re
import time
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlsplit, urlunsplit

try:  # orjson is optional: several times faster than json, but a compiled wheel
    import orjson as _orjson
except ImportError:  # pragma: no cover - depends on the installation
    _orjson = None  # type: ignore[assignment]

DEVICE_WS_PATH = "/api/v1/device/ws"
MAX_BATCH_SAMPLES = 100_000
MAX_FRAME_BYTES = 16 * 1024 * 1024
STREAM_NAME = re.compile(r"^[a-z][a-z0-9_-]{0,63}$")
MAX_SEQ = 2**63 - 1

JsonObject = dict[str, Any]


class BufferFull(Exception):
    """The store-and-forward buffer holds `max_buffered_samples` samples and the policy
    (`on_full="error"`, or `"block"` where blocking is impossible) refuses one more."""


def _default(value: Any) -> Any:
    """Values JSON does not know: numpy scalars and the like become numbers, others text."""
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).decode("utf-8", "replace")
    if hasattr(value, "__index__"):
        return int(value.__index__())
    try:
        return float(value)
    except (TypeError, ValueError):
        return str(value)


def _finite(value: Any) -> Any:
    """`value` with every NaN or infinity replaced by None (the server rejects that sample
    alone; stdlib json would write `NaN`, which is not JSON, and lose the whole batch)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def encode(obj: Any) -> tuple[str, int]:
    """`obj` as compact JSON text, and its size in UTF-8 bytes."""
    if _orjson is not None:
        try:
            raw = _orjson.dumps(obj, default=_default, option=_orjson.OPT_SERIALIZE_NUMPY)
            return raw.decode(), len(raw)
        except TypeError:  # e.g. keys that are not strings: let json say it
            pass
    try:
        text = json.dumps(obj, separators=(",", ":"), allow_nan=False, default=_default)
    except ValueError:
        text = json.dumps(_finite(obj), separators=(",", ":"), default=_default)
    return text, len(text)  # ensure_ascii: one byte a character


def dumps(obj: Any) -> str:
    return encode(obj)[0]


def loads(data: str | bytes) -> Any:
    if _orjson is not None:
        return _orjson.loads(data)
    return json.loads(data)


def device_ws_url(url: str) -> str:
    """The device WebSocket URL for a server URL: `http(s)://host[/prefix]` becomes
    `ws(s)://host[/prefix]/api/v1/device/ws`; a ws(s) URL is taken as it is when it already
    ends with that path."""
    parts = urlsplit(url.strip())
    scheme = {"http": "ws", "https": "wss", "ws": "ws", "wss": "wss"}.get(parts.scheme.lower())
    if scheme is None or not parts.netloc:
        raise ValueError(f"not an http(s) or ws(s) URL: {url!r}")
    path = parts.path.rstrip("/")
    if not path.endswith(DEVICE_WS_PATH):
        path += DEVICE_WS_PATH
    return urlunsplit((scheme, parts.netloc, path, parts.query, ""))


def check_stream(name: str) -> str:
    if not isinstance(name, str) or not STREAM_NAME.match(name):
        raise ValueError(f"stream names match {STREAM_NAME.pattern}, not {name!r}")
    return name


class SeqCounter:
    """Batch sequence numbers: the current time in microseconds, and +1 a batch when batches
    come faster than that, so a restarted device never reuses one (while its clock does not
    go back; a disk buffer also remembers the last one, `floor`)."""

    def __init__(self, floor: int = 0) -> None:
        self.last = floor

    def next(self) -> int:
        self.last = max(self.last + 1, time.time_ns() // 1000)
        if self.last > MAX_SEQ:  # pragma: no cover - in the year 294 000
            raise OverflowError("sequence numbers exhausted")
        return self.last


class Backoff:
    """Reconnect delays: `initial` doubling up to `maximum`, each drawn at random from the
    upper half of its range so devices that lost one server do not all come back at once."""

    def __init__(
        self, initial: float = 0.1, maximum: float = 10.0, rng: random.Random | None = None
    ) -> None:
        if not 0 < initial <= maximum:
            raise ValueError("backoff needs 0 < initial <= maximum")
        self.initial = initial
        self.maximum = maximum
        self.attempt = 0
        self._rng = rng or random.Random()

    def ceiling(self) -> float:
        """The largest delay the next call may return."""
        return min(self.maximum, self.initial * 2.0 ** min(self.attempt, 64))

    def next(self) -> float:
        top = self.ceiling()
        self.attempt += 1
        return top / 2 + self._rng.random() * top / 2

    def reset(self) -> None:
        self.attempt = 0


@dataclass
class Ack:
    """The server's answer to one batch (`type: ack`), or a batch refused whole (`error`
    with its `seq`: then `refused` is the error text and every sample counts as rejected)."""

    seq: int
    accepted: int = 0
    rejected_count: int = 0
    rejected: list[tuple[int, str]] = field(default_factory=list)
    server_timed: int = 0
    duplicate: bool = False
    dropped: int = 0  # signals left out of samples (the interface drops unknown signals)
    refused: str | None = None
    raw: JsonObject = field(default_factory=dict)

    @classmethod
    def from_message(cls, msg: JsonObject) -> Ack:
        rejected: list[tuple[int, str]] = []
        for item in msg.get("rejected") or []:
            if isinstance(item, dict):
                rejected.append((_int(item.get("index"), -1), str(item.get("reason", ""))))
        return cls(
            seq=_int(msg.get("seq")),
            accepted=_int(msg.get("accepted")),
            rejected_count=_int(msg.get("rejected_count"), len(rejected)),
            rejected=rejected,
            server_timed=_int(msg.get("server_timed")),
            duplicate=bool(msg.get("duplicate", False)),
            dropped=_int(msg.get("dropped")),
            raw=msg,
        )


def _int(value: Any, default: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        return default
    return value


def sample(values: JsonObject, time_ns: int | None) -> JsonObject:
    if not isinstance(values, dict) or not values:
        raise ValueError("a sample needs a non-empty dict of values")
    return {"time": time.time_ns() if time_ns is None else int(time_ns), "values": dict(values)}


def batch_message(seq: int, stream: str, samples: list[JsonObject]) -> JsonObject:
    return {"type": "samples", "seq": seq, "stream": stream, "time_unit": "ns", "samples": samples}
