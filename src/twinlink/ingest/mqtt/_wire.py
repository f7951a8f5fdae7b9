"""MQTT's primitive encodings (variable byte integers, strings, MQTT 5 properties), shared by
the packet codec in `packets.py`. Section numbers refer to the MQTT 5.0 standard; 3.1.1 uses
the same encodings without properties."""

from __future__ import annotations

import struct
from typing import Any

MAX_VARINT = 268_435_455  # 4 bytes of 7 bits
Buffer = bytes | bytearray | memoryview


class MalformedPacket(Exception):
    """Bytes that are not a valid MQTT packet; the connection is closed (v5: reason 0x81)."""

    # Not a TwinlinkError: control flow of an MQTT connection, which it ends with a
    # DISCONNECT; the client is told by the reason code, never by an HTTP answer.


def encode_varint(value: int) -> bytes:
    """A variable byte integer (1.5.5): 7 bits a byte, low first, high bit = more."""
    if value < 128:
        return bytes((value,))
    out = bytearray()
    while True:
        byte, value = value & 0x7F, value >> 7
        out.append(byte | 0x80 if value else byte)
        if not value:
            return bytes(out)


def decode_varint(data: Buffer, pos: int) -> tuple[int, int]:
    """The integer at `pos` and the position after it; MalformedPacket when it runs past the
    data or is longer than 4 bytes."""
    value = shift = 0
    for i in range(4):
        if pos + i >= len(data):
            raise MalformedPacket("a variable byte integer runs past the packet")
        byte = data[pos + i]
        value |= (byte & 0x7F) << shift
        if not byte & 0x80:
            return value, pos + i + 1
        shift += 7
    raise MalformedPacket("a variable byte integer is longer than 4 bytes")


def encode_str(text: str) -> bytes:
    raw = text.encode()
    return struct.pack("!H", len(raw)) + raw


def encode_bin(raw: bytes) -> bytes:
    return struct.pack("!H", len(raw)) + raw


class Cursor:
    """Reads the fields of one packet body, in order."""

    __slots__ = ("data", "end", "pos")

    def __init__(self, data: Buffer, pos: int = 0, end: int | None = None) -> None:
        self.data = data
        self.pos = pos
        self.end = len(data) if end is None else end

    def left(self) -> int:
        return self.end - self.pos

    def _take(self, n: int) -> bytes:
        if self.pos + n > self.end:
            raise MalformedPacket("a field runs past the end of the packet")
        chunk = bytes(self.data[self.pos : self.pos + n])
        self.pos += n
        return chunk

    def byte(self) -> int:
        return self._take(1)[0]

    def u16(self) -> int:
        value: int = struct.unpack("!H", self._take(2))[0]
        return value

    def u32(self) -> int:
        value: int = struct.unpack("!I", self._take(4))[0]
        return value

    def varint(self) -> int:
        value, self.pos = decode_varint(self.data, self.pos)
        if self.pos > self.end:
            raise MalformedPacket("a variable byte integer runs past the packet")
        return value

    def binary(self) -> bytes:
        return self._take(self.u16())

    def text(self) -> str:
        raw = self.binary()
        try:
            text = raw.decode()
        except UnicodeDecodeError as err:
            raise MalformedPacket("a string is not UTF-8") from err
        if "\x00" in text:
            raise MalformedPacket("a string holds U+0000")
        return text

    def rest(self) -> bytes:
        return self._take(self.left())

    def properties(self) -> dict[int, Any]:
        """An MQTT 5 property list (2.2.2). Repeatable ones (user property 0x26, subscription
        identifier 0x0B) are lists; others appearing twice are a protocol error."""
        length = self.varint()
        stop = self.pos + length
        if stop > self.end:
            raise MalformedPacket("the properties run past the end of the packet")
        found: dict[int, Any] = {}
        while self.pos < stop:
            key = self.varint()
            kind = PROPERTY_KINDS.get(key)
            if kind is None:
                raise MalformedPacket(f"unknown property 0x{key:02x}")
            value = _READERS[kind](self)
            if key in (USER_PROPERTY, SUBSCRIPTION_ID):
                found.setdefault(key, []).append(value)
            elif key in found:
                raise MalformedPacket(f"property 0x{key:02x} appears twice")
            else:
                found[key] = value
        if self.pos != stop:
            raise MalformedPacket("a property runs past the property list")
        return found


# Property identifiers (MQTT 5.0, 2.2.2.2) and the type of each one's value.
PAYLOAD_FORMAT = 0x01
MESSAGE_EXPIRY = 0x02
CONTENT_TYPE = 0x03
RESPONSE_TOPIC = 0x08
CORRELATION_DATA = 0x09
SUBSCRIPTION_ID = 0x0B
SESSION_EXPIRY = 0x11
ASSIGNED_CLIENT_ID = 0x12
SERVER_KEEP_ALIVE = 0x13
AUTH_METHOD = 0x15
AUTH_DATA = 0x16
REQUEST_PROBLEM_INFO = 0x17
WILL_DELAY = 0x18
REQUEST_RESPONSE_INFO = 0x19
RESPONSE_INFO = 0x1A
SERVER_REFERENCE = 0x1C
REASON_STRING = 0x1F
RECEIVE_MAXIMUM = 0x21
TOPIC_ALIAS_MAXIMUM = 0x22
TOPIC_ALIAS = 0x23
MAXIMUM_QOS = 0x24
RETAIN_AVAILABLE = 0x25
USER_PROPERTY = 0x26
MAXIMUM_PACKET_SIZE = 0x27
WILDCARD_AVAILABLE = 0x28
SUBSCRIPTION_ID_AVAILABLE = 0x29
SHARED_AVAILABLE = 0x2A

PROPERTY_KINDS: dict[int, str] = {
    PAYLOAD_FORMAT: "byte", MESSAGE_EXPIRY: "u32", CONTENT_TYPE: "text",
    RESPONSE_TOPIC: "text", CORRELATION_DATA: "binary", SUBSCRIPTION_ID: "varint",
    SESSION_EXPIRY: "u32", ASSIGNED_CLIENT_ID: "text", SERVER_KEEP_ALIVE: "u16",
    AUTH_METHOD: "text", AUTH_DATA: "binary", REQUEST_PROBLEM_INFO: "byte",
    WILL_DELAY: "u32", REQUEST_RESPONSE_INFO: "byte", RESPONSE_INFO: "text",
    SERVER_REFERENCE: "text", REASON_STRING: "text", RECEIVE_MAXIMUM: "u16",
    TOPIC_ALIAS_MAXIMUM: "u16", TOPIC_ALIAS: "u16", MAXIMUM_QOS: "byte",
    RETAIN_AVAILABLE: "byte", USER_PROPERTY: "pair", MAXIMUM_PACKET_SIZE: "u32",
    WILDCARD_AVAILABLE: "byte", SUBSCRIPTION_ID_AVAILABLE: "byte", SHARED_AVAILABLE: "byte",
}  # fmt: skip

_READERS: dict[str, Any] = {
    "byte": Cursor.byte,
    "u16": Cursor.u16,
    "u32": Cursor.u32,
    "varint": Cursor.varint,
    "text": Cursor.text,
    "binary": Cursor.binary,
    "pair": lambda c: (c.text(), c.text()),
}


def encode_properties(props: dict[int, Any] | None) -> bytes:
    """The property list of `props` (key -> value; lists for repeatable keys)."""
    if not props:
        return b"\x00"
    out = bytearray()
    for key, value in props.items():
        for item in value if key in (USER_PROPERTY, SUBSCRIPTION_ID) else (value,):
            out += encode_varint(key)
            out += _encode_value(PROPERTY_KINDS[key], item)
    return encode_varint(len(out)) + bytes(out)


def _encode_value(kind: str, value: Any) -> bytes:
    if kind == "byte":
        return bytes((value,))
    if kind == "u16":
        return struct.pack("!H", value)
    if kind == "u32":
        return struct.pack("!I", value)
    if kind == "varint":
        return encode_varint(value)
    if kind == "text":
        return encode_str(value)
    if kind == "binary":
        return encode_bin(value)
    return encode_str(value[0]) + encode_str(value[1])
