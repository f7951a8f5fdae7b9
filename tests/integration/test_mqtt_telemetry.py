"""Telemetry over the embedded MQTT listener, from real clients (mosquitto_pub with MQTT 3.1.1
and 5, paho-mqtt with both): every payload form lands in history, a QoS 1 PUBACK comes only
once the batch is durable, bad tokens are refused with the CONNACK code, and malformed
payloads and unknown topics are told on the device's `errors` topic and counted."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import orjson
import pytest

from tests.integration._mqtt import (
    MqttPlatform,
    Paho,
    mosquitto_pub,
    mqtt_platform,
    require_mosquitto,
    until,
)
from twinlink.ingest.mqtt import packets as mq

pytestmark = pytest.mark.integration

T0 = 1_790_000_000_000_000_000  # 2026-09-21


@pytest.fixture
async def platform(tmp_path: Path) -> AsyncIterator[MqttPlatform]:
    require_mosquitto()
    async with mqtt_platform(tmp_path / "data") as p:
        yield p


@pytest.mark.parametrize(
    "options",
    [["-q", "0"], ["-q", "1"], ["-q", "1", "-V", "mqttv5"], ["-q", "2"], ["-q", "2", "-V", "5"]],
)
async def test_mosquitto_pub_flat_values(platform: MqttPlatform, options: list[str]) -> None:
    rc, out = await mosquitto_pub(
        platform.port, "-u", "rig", "-P", platform.token, "-t", platform.topic("telemetry"),
        "-m", '{"angle": 0.1, "force": 2.5}', *options,
    )  # fmt: skip
    assert rc == 0, out
    [row] = await platform.rows_until(1)
    assert row["values"] == {"angle": 0.1, "force": 2.5}
    assert platform.status()["received"] == {"telemetry": 1}


async def test_the_token_may_be_the_username(platform: MqttPlatform) -> None:
    rc, out = await mosquitto_pub(
        platform.port, "-u", platform.token, "-t", platform.topic("telemetry"), "-m", '{"angle": 1}'
    )
    assert rc == 0, out
    await platform.rows_until(1)


@pytest.mark.parametrize("version", [4, 5])
async def test_paho_batches_samples_lists_and_streams(platform: MqttPlatform, version: int) -> None:
    device = Paho(platform.port, "rig", platform.token, version)
    assert (await device.connect()).value == 0
    try:
        assert await device.subscribe(platform.topic("acks")) == [1]
        batch = {"seq": 41, "samples": [{"time": T0 + 1, "values": {"angle": 0.5}},
                                        {"time": T0 + 2, "values": {"angle": 0.6}}]}  # fmt: skip
        assert await device.publish(platform.topic("telemetry"), orjson.dumps(batch)) == 0
        topic, payload = await device.message()
        ack = orjson.loads(payload)
        assert topic == platform.topic("acks")
        assert ack["type"] == "ack" and (ack["seq"], ack["accepted"]) == (41, 2), ack
        # The same batch again (a resend): acknowledged as a duplicate, stored once.
        await device.publish(platform.topic("telemetry"), orjson.dumps(batch))
        assert orjson.loads((await device.message())[1])["duplicate"] is True
        samples = [{"time": T0 + 3, "values": {"angle": 0.7}}, {"values": {"angle": 0.8}}]
        await device.publish(platform.topic("telemetry"), orjson.dumps(samples))
        one = {"time": T0 + 4, "values": {"x": 1}}
        await device.publish(platform.topic("telemetry"), orjson.dumps(one))
        await device.publish(platform.topic("telemetry/fast"), b'{"angle": 9}', qos=0)
        await device.publish(platform.topic("telemetry/fast"), b'{"angle": 10}', qos=1)
    finally:
        await device.stop()
    rows = await platform.rows_until(5)
    assert [r["time"] - T0 for r in rows[:4]] == [1, 2, 3, 4]
    assert [r["values"] for r in await platform.rows_until(2, "fast")] == [
        {"angle": 9}, {"angle": 10},
    ]  # fmt: skip


async def _raw_device(platform: MqttPlatform, version: int = mq.V311) -> Any:
    reader, writer = await asyncio.open_connection("127.0.0.1", platform.port)
    packets = mq.PacketReader(1 << 20, version)
    writer.write(mq.encode_connect(version, "raw", True, 60, "rig", platform.token))
    return reader, writer, packets


async def _read(reader: asyncio.StreamReader, packets: mq.PacketReader) -> list[mq.Packet]:
    async with asyncio.timeout(10):
        while not (got := packets.feed(await reader.read(65536))):
            pass
    return got


async def test_qos1_is_acknowledged_only_once_the_batch_is_durable(
    platform: MqttPlatform,
) -> None:
    history = platform.services.history
    release = asyncio.Event()
    append = history.append

    async def held_append(*args: Any, **kwargs: Any) -> bool:
        await release.wait()  # the disk is slow: the commit has not happened yet
        return await append(*args, **kwargs)

    history.append = held_append  # type: ignore[method-assign]
    reader, writer, packets = await _raw_device(platform)
    try:
        assert await _read(reader, packets) == [mq.ConnAck(False, mq.SUCCESS)]
        writer.write(mq.encode_publish(mq.V311, platform.topic("telemetry"), b'{"angle": 1}', 1, 7))
        writer.write(mq.PINGREQ_BYTES)
        # The PINGRESP is written after the PUBLISH was read and handed on: no PUBACK yet.
        assert await _read(reader, packets) == [mq.Simple(mq.PINGRESP)]
        assert await platform.rows() == []
        release.set()
        assert await _read(reader, packets) == [mq.Ack(mq.PUBACK, 7)]
        assert len(await platform.rows()) == 1  # durable when acknowledged
    finally:
        writer.close()


async def test_a_burst_of_one_sample_messages_is_stored_as_one_batch(
    platform: MqttPlatform,
) -> None:
    reader, writer, packets = await _raw_device(platform)
    try:
        await _read(reader, packets)
        burst = b"".join(
            mq.encode_publish(mq.V311, platform.topic("telemetry"), b'{"angle": %d}' % i, 1, i)
            for i in range(1, 201)
        )
        writer.write(burst)
        acked: list[int] = []
        while len(acked) < 200:
            acked += [p.packet_id for p in await _read(reader, packets) if isinstance(p, mq.Ack)]
        assert sorted(acked) == list(range(1, 201))
    finally:
        writer.close()
    rows = await platform.rows_until(200)
    assert [r["values"]["angle"] for r in rows] == list(range(1, 201))  # distinct, ordered times
    assert platform.services.history.writer.commits < 200


@pytest.mark.parametrize(
    ("credentials", "code", "text"),
    [
        (["-u", "rig", "-P", "tld_wrong"], 4, "bad user name or password"),
        ([], 5, "not authorised"),
    ],
)
async def test_mosquitto_pub_with_a_bad_token_is_refused(
    platform: MqttPlatform, credentials: list[str], code: int, text: str
) -> None:
    rc, out = await mosquitto_pub(
        platform.port, *credentials, "-t", platform.topic("telemetry"), "-m", "{}"
    )
    assert rc != 0 and text in out.lower(), out
    assert sum(platform.status()["refused"].values()) == 1
    assert await platform.rows() == []


async def test_paho_v5_bad_token_gets_reason_134(platform: MqttPlatform) -> None:
    device = Paho(platform.port, "rig", "tld_wrong", 5)
    reason = await device.connect()
    assert reason.value == mq.BAD_CREDENTIALS and str(reason) == "Bad user name or password"
    assert platform.status()["refused"] == {"bad_token": 1}


@pytest.mark.parametrize("version", [4, 5])
async def test_malformed_payloads_are_told_and_counted(
    platform: MqttPlatform, version: int
) -> None:
    device = Paho(platform.port, "rig", platform.token, version)
    await device.connect()
    try:
        await device.subscribe(platform.topic("errors"))
        reason = await device.publish(platform.topic("telemetry"), b"not json")
        assert reason == (mq.PAYLOAD_FORMAT_INVALID if version == 5 else 0)
        error = orjson.loads((await device.message())[1])
        assert error["type"] == "error" and "not JSON" in error["message"]
        # A readable batch with one bad sample: the good one is kept, the bad one told.
        mixed = b'[{"values": {"angle": "x"}}, {"values": {"angle": 2}}]'
        await device.publish(platform.topic("telemetry"), mixed)
        error = orjson.loads((await device.message())[1])
        assert error["message"].startswith("1 sample(s) rejected; #0: angle")
        # The device stays connected and its next message is stored.
        assert await device.publish(platform.topic("telemetry"), b'{"angle": 3}') == 0
    finally:
        await device.stop()
    assert [r["values"] for r in await platform.rows_until(2)] == [{"angle": 2}, {"angle": 3}]
    errors = platform.status()["errors"]
    assert errors == {"malformed": 1, "rejected_samples": 1}


@pytest.mark.parametrize(
    ("suffix", "kind", "reason"),
    [
        ("telemetri", "unknown_topic", mq.TOPIC_NAME_INVALID),
        ("properties/desired", "unknown_topic", mq.TOPIC_NAME_INVALID),
        ("telemetry@other", "not_authorized", mq.NOT_AUTHORIZED),
    ],
)
async def test_unknown_topics_are_refused_and_counted(
    platform: MqttPlatform, suffix: str, kind: str, reason: int
) -> None:
    await platform.add_device("other")
    topic = platform.topic(suffix.split("@")[0], suffix.split("@")[1] if "@" in suffix else None)
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await device.subscribe(platform.topic("errors"))
        assert await device.publish(topic, b'{"angle": 1}') == reason
        assert topic in orjson.loads((await device.message())[1])["message"]
    finally:
        await device.stop()
    assert platform.status()["errors"] == {kind: 1}
    assert await platform.rows() == []


async def test_disconnect_and_come_back(platform: MqttPlatform) -> None:
    hub = platform.services.device_hub
    device = Paho(platform.port, "rig", platform.token, 4)
    await device.connect()
    await until(lambda: hub.session(platform.device.id) is not None, "the device's session")
    await device.publish(platform.topic("telemetry"), b'{"angle": 1}')
    await device.stop()
    await until(lambda: hub.session(platform.device.id) is None, "the session to end")
    again = Paho(platform.port, "rig", platform.token, 5)
    await again.connect()
    try:
        await until(lambda: hub.session(platform.device.id) is not None, "a new session")
        await again.publish(platform.topic("telemetry"), b'{"angle": 2}')
    finally:
        await again.stop()
    assert [r["values"]["angle"] for r in await platform.rows_until(2)] == [1, 2]
    assert platform.status()["connects"] == 2


async def test_a_newer_connection_of_the_device_takes_over(platform: MqttPlatform) -> None:
    first = Paho(platform.port, "rig", platform.token, 5, client_id="one")
    await first.connect()
    second = Paho(platform.port, "rig", platform.token, 5, client_id="two")
    await second.connect()
    try:
        await until(first.disconnected.is_set, "the first connection to be ended")
        assert first.disconnect_reason is not None
        assert first.disconnect_reason.value == mq.SESSION_TAKEN_OVER
        assert await second.publish(platform.topic("telemetry"), b'{"angle": 1}') == 0
    finally:
        first.client.loop_stop()
        await second.stop()


async def test_a_revoked_token_ends_the_connection(
    platform: MqttPlatform, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(platform.services.devices, "recheck_token_s", 0.05)
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await platform.services.devices.rotate(platform.admin, platform.slug, "rig")
        await until(device.disconnected.is_set, "the connection to be ended")
        assert device.disconnect_reason is not None
        assert device.disconnect_reason.value == mq.NOT_AUTHORIZED
    finally:
        await device.stop()


async def test_a_silent_client_is_dropped_after_its_keep_alive(platform: MqttPlatform) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", platform.port)
    writer.write(mq.encode_connect(mq.V5, "quiet", True, 1, "rig", platform.token))
    packets = mq.PacketReader(1 << 16, mq.V5)
    try:
        got = await _read(reader, packets)
        assert isinstance(got[0], mq.ConnAck)
        # Nothing sent: after 1.5 keep-alives the server says why and closes.
        got = await _read(reader, packets)
        assert got == [mq.Simple(mq.DISCONNECT, mq.KEEP_ALIVE_TIMEOUT)]
        async with asyncio.timeout(10):
            assert await reader.read() == b""
    finally:
        writer.close()
    assert platform.status()["errors"] == {"keep_alive": 1}


async def test_a_port_in_use_is_a_clear_error(tmp_path: Path, platform: MqttPlatform) -> None:
    from twinlink.ingest.mqtt.listener import ListenerError

    with pytest.raises(ListenerError, match=f"cannot listen on 127.0.0.1:{platform.port}"):
        async with mqtt_platform(tmp_path / "second", mqtt_port=platform.port):
            pass
