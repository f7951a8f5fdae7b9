"""What a Kafka record of the bus holds: the subject and the message, in MessagePack.

MessagePack keeps what JSON would lose: an int stays an int (every int64 exactly, where JSON
readers turn big ones into floats), a float stays a float (1.0 is not 1), bytes stay bytes.
A `SampleBatch` (the bus's unit today) is written as an array of its fields, not a map, so a
record carries no field names; its samples stay the dicts they are, which msgspec writes in C
without a Python step per sample. Anything else MessagePack can hold (None, bool, int64,
float, str, bytes, lists, dicts) is carried as it is; tuples and sets come back as lists.

The record is `[kind, subject, ...]`; `kind` says how to read the rest, so a later kind can be
added without breaking nodes that still run this code (they log and skip what they cannot read).
"""

from __future__ import annotations

from typing import Any

import msgspec

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.samples import SampleBatch

PLAIN = 0
BATCH = 1


class UnencodableMessageError(InvalidInputError):
    """A message the Kafka bus cannot carry (an object MessagePack has no form for)."""


class UndecodableRecordError(ValueError):
    """A record on a bus topic that is not one this code wrote (or a later kind of one)."""

    # Not a TwinlinkError: control flow of the bus's reader, which logs the record and skips
    # it; no request is answered with it.


def _numpy_scalar(obj: Any) -> Any:
    # numpy's float64 and int64 are not floats and ints to msgspec; .item() makes them so. Only
    # called for types msgspec cannot write itself, so it costs nothing on the usual path.
    item = getattr(obj, "item", None)
    if callable(item) and type(obj).__module__ == "numpy":
        return item()
    raise TypeError(f"objects of type {type(obj).__qualname__} cannot go on the bus")


_encoder = msgspec.msgpack.Encoder(enc_hook=_numpy_scalar)
_decoder = msgspec.msgpack.Decoder()


def encode(subject: str, message: object) -> bytes:
    try:
        if isinstance(message, SampleBatch):
            b = message
            fields = (BATCH, subject, b.twin_id, b.twin, b.stream, b.times, b.values, b.received_ns)
            return _encoder.encode((*fields, b.source, b.seq))
        return _encoder.encode((PLAIN, subject, message))
    except (TypeError, OverflowError) as err:
        raise UnencodableMessageError(
            f"the message for {subject} cannot be sent over Kafka: {err} (the bus carries "
            "sample batches and plain data: None, bool, int64, float, str, bytes, lists, dicts)"
        ) from err


def decode(record: bytes) -> tuple[str, object]:
    """The subject and message of a record written by `encode`."""
    try:
        fields = _decoder.decode(record)
    except msgspec.DecodeError as err:
        raise UndecodableRecordError(f"not MessagePack: {err}") from err
    if not isinstance(fields, list) or len(fields) < 3 or not isinstance(fields[1], str):
        raise UndecodableRecordError("not a [kind, subject, ...] array")
    kind, subject = fields[0], fields[1]
    if kind == PLAIN and len(fields) == 3:
        return subject, fields[2]
    if kind == BATCH and len(fields) == 10:
        return subject, SampleBatch(*fields[2:])
    raise UndecodableRecordError(f"unknown kind {kind!r} with {len(fields)} fields")
