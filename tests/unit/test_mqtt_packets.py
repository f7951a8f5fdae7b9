"""The MQTT codec: what it encodes reads back, packets split anywhere arrive whole, and bytes
that break the protocol are refused with the reason MQTT 5 gives them."""

from __future__ import annotations

import pytest

from twinlink.ingest.mqtt import packets as mq
from twinlink.ingest.mqtt._wire import (
    MAXIMUM_PACKET_SIZE,
    REASON_STRING,
    USER_PROPERTY,
    Cursor,
    MalformedPacket,
    decode_varint,
    encode_properties,
    encode_varint,
)


@pytest.mark.parametrize("value", [0, 1, 127, 128, 16_383, 16_384, 2_097_151, 268_435_455])
def test_varint_round_trip(value: int) -> None:
    encoded = encode_varint(value)
    assert decode_varint(encoded, 0) == (value, len(encoded))
    assert len(encoded) == 1 + (value > 127) + (value > 16_383) + (value > 2_097_151)


def test_varint_longer_than_four_bytes_is_malformed() -> None:
    with pytest.raises(MalformedPacket, match="longer than 4"):
        decode_varint(b"\xff\xff\xff\xff\x01", 0)


def test_properties_round_trip() -> None:
    props = {MAXIMUM_PACKET_SIZE: 1 << 20, REASON_STRING: "because",
             USER_PROPERTY: [("a", "1"), ("b", "2")]}  # fmt: skip
    assert Cursor(encode_properties(props)).properties() == props


def test_a_property_twice_is_malformed() -> None:
    raw = encode_properties({REASON_STRING: "x"})[1:] * 2
    with pytest.raises(MalformedPacket, match="twice"):
        Cursor(encode_varint(len(raw)) + raw).properties()


@pytest.mark.parametrize("version", [mq.V311, mq.V5])
def test_connect_reads_back(version: int) -> None:
    raw = mq.encode_connect(version, "dev-1", True, 30, "rig", "tld_secret")
    [packet] = mq.PacketReader(1024).feed(raw)
    assert packet == mq.Connect(version, "dev-1", True, 30, "rig", b"tld_secret")


def test_connect_of_mqtt_31_reads_as_311() -> None:
    body = b"\x00\x06MQIsdp\x03\x02\x00\x3c\x00\x01c"
    [packet] = mq.PacketReader(1024).feed(bytes((0x10, len(body))) + body)
    assert isinstance(packet, mq.Connect) and packet.version == mq.V311


def test_connect_with_will_and_v5_properties() -> None:
    # CONNECT v5: will flag, QoS 1, username; will properties and topic/payload present.
    body = (
        b"\x00\x04MQTT\x05" + bytes((0x80 | 0x08 | 0x04 | 0x02,)) + b"\x00\x0a"
        + encode_properties({0x11: 60}) + b"\x00\x01c" + b"\x00" + b"\x00\x01w"
        + b"\x00\x03bye" + b"\x00\x03tok"
    )  # fmt: skip
    [packet] = mq.PacketReader(1024).feed(bytes((0x10, len(body))) + body)
    assert isinstance(packet, mq.Connect)
    assert packet.will == mq.Will("w", b"bye", 1, False)
    assert (packet.username, packet.password, packet.properties) == ("tok", None, {0x11: 60})


def test_unknown_protocol_level_is_refused_as_unsupported() -> None:
    body = b"\x00\x04MQTT\x06\x02\x00\x3c\x00\x01c"
    with pytest.raises(mq.ProtocolViolation) as caught:
        mq.PacketReader(1024).feed(bytes((0x10, len(body))) + body)
    assert caught.value.reason == mq.UNSUPPORTED_VERSION


@pytest.mark.parametrize("version", [mq.V311, mq.V5])
@pytest.mark.parametrize("qos", [0, 1, 2])
def test_publish_reads_back(version: int, qos: int) -> None:
    raw = mq.encode_publish(version, "a/b", b'{"x": 1}', qos, 7 if qos else 0, retain=True)
    reader = mq.PacketReader(1024, version)
    [packet] = reader.feed(raw)
    assert isinstance(packet, mq.Publish)
    assert (packet.topic, packet.payload, packet.qos) == ("a/b", b'{"x": 1}', qos)
    assert packet.retain
    assert packet.packet_id == (7 if qos else 0)


def test_packets_split_at_every_byte_arrive_whole() -> None:
    stream = (
        b"".join(mq.encode_publish(mq.V5, "t", bytes(range(200)) * i, 1, i + 1) for i in range(3))
        + mq.PINGREQ_BYTES
    )
    reader = mq.PacketReader(1 << 16, mq.V5)
    got = [p for i in range(len(stream)) for p in reader.feed(stream[i : i + 1])]
    assert [type(p).__name__ for p in got] == ["Publish", "Publish", "Publish", "Simple"]
    assert [len(p.payload) for p in got if isinstance(p, mq.Publish)] == [0, 200, 400]


def test_a_packet_over_the_limit_is_refused_before_it_is_read() -> None:
    head = b"\x30" + encode_varint(10_000)
    with pytest.raises(mq.ProtocolViolation) as caught:
        mq.PacketReader(1000).feed(head)
    assert caught.value.reason == mq.PACKET_TOO_LARGE


@pytest.mark.parametrize(
    ("raw", "why"),
    [
        (b"\x36\x05\x00\x01t\x00\x01", "QoS 3"),
        (b"\x32\x05\x00\x01t\x00\x00", "packet id 0"),
        (b"\x82\x02\x00\x01", "without a topic filter"),
        (b"\xc1\x00", "flags"),
        (b"\x32\x03\x00\x05t", "past the end"),
        (b"\x30\x04\x00\x02\xff\xfe", "UTF-8"),
    ],
)
def test_malformed_packets(raw: bytes, why: str) -> None:
    with pytest.raises(MalformedPacket, match=why):
        mq.PacketReader(1024).feed(raw)


@pytest.mark.parametrize("version", [mq.V311, mq.V5])
def test_acks_subscribe_and_suback(version: int) -> None:
    reader = mq.PacketReader(1024, version)
    raw = (
        mq.encode_ack(mq.PUBACK, 5, version, mq.PAYLOAD_FORMAT_INVALID)
        + mq.encode_subscribe(version, 9, [("a/+", 1), ("b/#", 0)])
        + mq.encode_suback(version, 9, [1, 0x80])
    )
    ack, subscribe, suback = reader.feed(raw)
    reason = mq.PAYLOAD_FORMAT_INVALID if version == mq.V5 else mq.SUCCESS
    assert ack == mq.Ack(mq.PUBACK, 5, reason)
    assert subscribe == mq.Subscribe(9, [("a/+", 1), ("b/#", 0)])
    assert suback == mq.SubAck(9, [1, 0x80])


@pytest.mark.parametrize(
    ("version", "reason", "wire"),
    [
        (mq.V311, mq.BAD_CREDENTIALS, b"\x20\x02\x00\x04"),
        (mq.V311, mq.NOT_AUTHORIZED, b"\x20\x02\x00\x05"),
        (mq.V311, mq.SUCCESS, b"\x20\x02\x00\x00"),
        (mq.V5, mq.BAD_CREDENTIALS, b"\x20\x03\x00\x86\x00"),
    ],
)
def test_connack_codes(version: int, reason: int, wire: bytes) -> None:
    assert mq.encode_connack(version, reason) == wire
    [packet] = mq.PacketReader(64, version).feed(wire)
    assert packet == mq.ConnAck(False, reason)


def test_disconnect_carries_a_reason_only_in_v5() -> None:
    assert mq.encode_disconnect(mq.V311, mq.SESSION_TAKEN_OVER) == b"\xe0\x00"
    raw = mq.encode_disconnect(mq.V5, mq.SESSION_TAKEN_OVER)
    [packet] = mq.PacketReader(64, mq.V5).feed(raw)
    assert packet == mq.Simple(mq.DISCONNECT, mq.SESSION_TAKEN_OVER)
