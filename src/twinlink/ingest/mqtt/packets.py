"""MQTT 3.1.1 and 5.0 packets: a sans-I/O reader that turns bytes into packets, and encoders.

Both the embedded listener (server side) and the client of an external broker use it. It
covers what a device platform needs: CONNECT/CONNACK, PUBLISH with QoS 0-2 and its acks,
SUBSCRIBE/UNSUBSCRIBE, PING and DISCONNECT. AUTH (MQTT 5 enhanced authentication) is read
only to be refused. MQTT 3.1 (protocol level 3) is read as 3.1.1.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from twinlink.ingest.mqtt._wire import (
    Cursor,
    MalformedPacket,
    encode_bin,
    encode_properties,
    encode_str,
    encode_varint,
)

CONNECT, CONNACK, PUBLISH, PUBACK, PUBREC, PUBREL, PUBCOMP = 1, 2, 3, 4, 5, 6, 7
SUBSCRIBE, SUBACK, UNSUBSCRIBE, UNSUBACK, PINGREQ, PINGRESP, DISCONNECT, AUTH = range(8, 16)

V311, V5 = 4, 5

# MQTT 5 reason codes used here (5.0, 2.4); CONNACK maps them to 3.1.1 return codes.
SUCCESS = 0x00
UNSPECIFIED_ERROR = 0x80
MALFORMED = 0x81
PROTOCOL_ERROR = 0x82
IMPLEMENTATION_ERROR = 0x83
UNSUPPORTED_VERSION = 0x84
CLIENT_ID_INVALID = 0x85
BAD_CREDENTIALS = 0x86
NOT_AUTHORIZED = 0x87
SERVER_UNAVAILABLE = 0x88
BAD_AUTH_METHOD = 0x8C
KEEP_ALIVE_TIMEOUT = 0x8D
SESSION_TAKEN_OVER = 0x8E
TOPIC_FILTER_INVALID = 0x8F
TOPIC_NAME_INVALID = 0x90
PACKET_TOO_LARGE = 0x95
PAYLOAD_FORMAT_INVALID = 0x99
QOS_NOT_SUPPORTED = 0x9B
SERVER_SHUTTING_DOWN = 0x8B
TOPIC_ALIAS_INVALID = 0x94

_V311_CONNACK = {
    SUCCESS: 0, UNSUPPORTED_VERSION: 1, CLIENT_ID_INVALID: 2, SERVER_UNAVAILABLE: 3,
    BAD_CREDENTIALS: 4, NOT_AUTHORIZED: 5, BAD_AUTH_METHOD: 5,
}  # fmt: skip
_V5_CONNACK = {v: k for k, v in _V311_CONNACK.items() if k != BAD_AUTH_METHOD}

PINGREQ_BYTES = b"\xc0\x00"
PINGRESP_BYTES = b"\xd0\x00"


class ProtocolViolation(MalformedPacket):
    """A well-formed packet that breaks the protocol (a second CONNECT, wrong flags); carries
    the MQTT 5 reason code for the DISCONNECT."""

    # Not a TwinlinkError, as MalformedPacket: it ends the connection with `reason`.

    def __init__(self, text: str, reason: int = PROTOCOL_ERROR) -> None:
        super().__init__(text)
        self.reason = reason


@dataclass(slots=True)
class Will:
    topic: str
    payload: bytes
    qos: int
    retain: bool


@dataclass(slots=True)
class Connect:
    version: int
    client_id: str
    clean_start: bool
    keep_alive: int
    username: str | None = None
    password: bytes | None = None
    will: Will | None = None
    properties: dict[int, Any] = field(default_factory=dict)


@dataclass(slots=True)
class ConnAck:
    session_present: bool
    reason: int  # an MQTT 5 reason code, whatever the version
    properties: dict[int, Any] = field(default_factory=dict)


@dataclass(slots=True)
class Publish:
    topic: str
    payload: bytes
    qos: int = 0
    retain: bool = False
    dup: bool = False
    packet_id: int = 0
    properties: dict[int, Any] | None = None


@dataclass(slots=True)
class Ack:
    """PUBACK, PUBREC, PUBREL or PUBCOMP (`kind`)."""

    kind: int
    packet_id: int
    reason: int = SUCCESS


@dataclass(slots=True)
class Subscribe:
    packet_id: int
    filters: list[tuple[str, int]]  # (filter, options: the QoS in bits 0-1)


@dataclass(slots=True)
class SubAck:
    packet_id: int
    codes: list[int]


@dataclass(slots=True)
class Unsubscribe:
    packet_id: int
    filters: list[str]


@dataclass(slots=True)
class Simple:
    """PINGREQ, PINGRESP, DISCONNECT, UNSUBACK and AUTH: a kind and perhaps a reason."""

    kind: int
    reason: int = SUCCESS
    packet_id: int = 0


Packet = Connect | ConnAck | Publish | Ack | Subscribe | SubAck | Unsubscribe | Simple

# The flags bits each packet type must carry (2.1.3); PUBLISH's are its own.
_FIXED_FLAGS = {PUBREL: 2, SUBSCRIBE: 2, UNSUBSCRIBE: 2}


class PacketReader:
    """Feed it bytes as they arrive; it returns the complete packets. `version` is what the
    CONNECT said (set it on the client side once the CONNECT is sent)."""

    def __init__(self, max_packet_bytes: int, version: int = V311) -> None:
        self.max_packet_bytes = max_packet_bytes
        self.version = version
        self._buffer = bytearray()

    def feed(self, data: bytes) -> list[Packet]:
        buf = self._buffer
        buf += data
        packets: list[Packet] = []
        pos, size = 0, len(buf)
        while size - pos >= 2:
            length, start = _frame_length(buf, pos)
            if length < 0:
                break  # the length itself is not complete yet
            if length > self.max_packet_bytes:
                raise ProtocolViolation(
                    f"a packet of {length} bytes; at most {self.max_packet_bytes}",
                    PACKET_TOO_LARGE,
                )
            if start + length > size:
                break
            packets.append(self._decode(buf[pos], Cursor(buf, start, start + length)))
            pos = start + length
        if pos:
            del buf[:pos]
        return packets

    def _decode(self, first: int, body: Cursor) -> Packet:
        kind, flags = first >> 4, first & 0x0F
        if kind == PUBLISH:
            return _publish(flags, body, self.version)
        if flags != _FIXED_FLAGS.get(kind, 0):
            raise MalformedPacket(f"packet type {kind} with flags {flags:#x}")
        if kind == CONNECT:
            packet = _connect(body)
            self.version = packet.version
            return packet
        decoder = _DECODERS.get(kind)
        if decoder is None:
            raise MalformedPacket(f"unknown packet type {kind}")
        return decoder(kind, body, self.version)


def _frame_length(buf: bytearray, pos: int) -> tuple[int, int]:
    """(remaining length, start of body) of the packet at `pos`; (-1, 0) when incomplete."""
    value = shift = 0
    for i in range(1, 5):
        if pos + i >= len(buf):
            return -1, 0
        byte = buf[pos + i]
        value |= (byte & 0x7F) << shift
        if not byte & 0x80:
            return value, pos + i + 1
        shift += 7
    raise MalformedPacket("the remaining length is longer than 4 bytes")


def _publish(flags: int, body: Cursor, version: int) -> Publish:
    qos = (flags >> 1) & 3
    if qos == 3:
        raise MalformedPacket("PUBLISH with QoS 3")
    topic = body.text()
    packet_id = body.u16() if qos else 0
    if qos and not packet_id:
        raise MalformedPacket("PUBLISH with QoS > 0 and packet id 0")
    props = body.properties() if version == V5 else None
    return Publish(topic, body.rest(), qos, bool(flags & 1), bool(flags & 8), packet_id, props)


def _connect(body: Cursor) -> Connect:
    name = body.text()
    version = body.byte()
    if name not in ("MQTT", "MQIsdp") or version not in (3, V311, V5):
        raise ProtocolViolation(f"protocol {name!r} level {version}", UNSUPPORTED_VERSION)
    flags = body.byte()
    if flags & 1:
        raise MalformedPacket("CONNECT with the reserved flag set")
    keep_alive = body.u16()
    props = body.properties() if version == V5 else {}
    connect = Connect(V5 if version == V5 else V311, body.text(), bool(flags & 2), keep_alive)
    connect.properties = props
    if flags & 4:
        if version == V5:
            body.properties()  # will properties: not used
        topic = body.text()
        connect.will = Will(topic, body.binary(), (flags >> 3) & 3, bool(flags & 32))
    if flags & 128:
        connect.username = body.text()
    if flags & 64:
        connect.password = body.binary()
    return connect


def _connack(kind: int, body: Cursor, version: int) -> ConnAck:
    present = bool(body.byte() & 1)
    code = body.byte()
    reason = code if version == V5 else _V5_CONNACK.get(code, UNSPECIFIED_ERROR)
    props = body.properties() if version == V5 and body.left() else {}
    return ConnAck(present, reason, props)


def _ack(kind: int, body: Cursor, version: int) -> Ack:
    packet_id = body.u16()
    reason = body.byte() if version == V5 and body.left() else SUCCESS
    if version == V5 and body.left():
        body.properties()
    return Ack(kind, packet_id, reason)


def _subscribe(kind: int, body: Cursor, version: int) -> Subscribe:
    packet_id = body.u16()
    if version == V5:
        body.properties()  # a subscription identifier is not kept
    filters = []
    while body.left():
        filters.append((body.text(), body.byte()))
    if not filters:
        raise ProtocolViolation("SUBSCRIBE without a topic filter")
    return Subscribe(packet_id, filters)


def _suback(kind: int, body: Cursor, version: int) -> SubAck:
    packet_id = body.u16()
    if version == V5:
        body.properties()
    return SubAck(packet_id, list(body.rest()))


def _unsubscribe(kind: int, body: Cursor, version: int) -> Unsubscribe:
    packet_id = body.u16()
    if version == V5:
        body.properties()
    filters = []
    while body.left():
        filters.append(body.text())
    if not filters:
        raise ProtocolViolation("UNSUBSCRIBE without a topic filter")
    return Unsubscribe(packet_id, filters)


def _simple(kind: int, body: Cursor, version: int) -> Simple:
    packet_id = body.u16() if kind == UNSUBACK else 0
    reason = body.byte() if kind in (DISCONNECT, AUTH) and body.left() else SUCCESS
    body.pos = body.end  # properties and UNSUBACK's reason codes are not used
    return Simple(kind, reason, packet_id)


_DECODERS: dict[int, Callable[[int, Cursor, int], Packet]] = {
    CONNACK: _connack, PUBACK: _ack, PUBREC: _ack, PUBREL: _ack, PUBCOMP: _ack,
    SUBSCRIBE: _subscribe, SUBACK: _suback, UNSUBSCRIBE: _unsubscribe, UNSUBACK: _simple,
    PINGREQ: _simple, PINGRESP: _simple, DISCONNECT: _simple, AUTH: _simple,
}  # fmt: skip


# -- encoders -----------------------------------------------------------------------------


def _frame(first: int, body: bytes) -> bytes:
    return bytes((first,)) + encode_varint(len(body)) + body


def encode_connack(
    version: int, reason: int, session_present: bool = False, props: dict[int, Any] | None = None
) -> bytes:
    if version == V5:
        return _frame(0x20, bytes((int(session_present), reason)) + encode_properties(props))
    code = _V311_CONNACK.get(reason, 3)
    return _frame(0x20, bytes((int(session_present and not code), code)))


def encode_publish(
    version: int,
    topic: str,
    payload: bytes,
    qos: int = 0,
    packet_id: int = 0,
    retain: bool = False,
    dup: bool = False,
) -> bytes:
    first = 0x30 | (8 if dup else 0) | (qos << 1) | int(retain)
    head = encode_str(topic) + (struct.pack("!H", packet_id) if qos else b"")
    return _frame(first, head + (b"\x00" if version == V5 else b"") + payload)


def encode_ack(kind: int, packet_id: int, version: int, reason: int = SUCCESS) -> bytes:
    """PUBACK, PUBREC, PUBREL or PUBCOMP; a reason only in MQTT 5 (3.1.1 has none)."""
    first = (kind << 4) | (2 if kind == PUBREL else 0)
    if version == V5 and reason != SUCCESS:
        return bytes((first, 3)) + struct.pack("!HB", packet_id, reason)
    return bytes((first, 2)) + struct.pack("!H", packet_id)


def encode_suback(version: int, packet_id: int, codes: list[int]) -> bytes:
    props = b"\x00" if version == V5 else b""
    return _frame(0x90, struct.pack("!H", packet_id) + props + bytes(codes))


def encode_unsuback(version: int, packet_id: int, count: int) -> bytes:
    if version == V5:
        return _frame(0xB0, struct.pack("!H", packet_id) + b"\x00" + bytes(count))
    return _frame(0xB0, struct.pack("!H", packet_id))


def encode_disconnect(version: int, reason: int = SUCCESS) -> bytes:
    return bytes((0xE0, 1, reason)) if version == V5 and reason else b"\xe0\x00"


def encode_connect(
    version: int,
    client_id: str,
    clean_start: bool,
    keep_alive: int,
    username: str | None = None,
    password: str | None = None,
    props: dict[int, Any] | None = None,
) -> bytes:
    flags = (2 if clean_start else 0) | (128 if username is not None else 0)
    flags |= 64 if password is not None else 0
    body = encode_str("MQTT") + bytes((version, flags)) + struct.pack("!H", keep_alive)
    body += encode_properties(props) if version == V5 else b""
    body += encode_str(client_id)
    body += encode_str(username) if username is not None else b""
    body += encode_bin(password.encode()) if password is not None else b""
    return _frame(0x10, body)


def encode_subscribe(version: int, packet_id: int, filters: list[tuple[str, int]]) -> bytes:
    body = struct.pack("!H", packet_id) + (b"\x00" if version == V5 else b"")
    for topic_filter, qos in filters:
        body += encode_str(topic_filter) + bytes((qos,))
    return _frame(0x82, body)
