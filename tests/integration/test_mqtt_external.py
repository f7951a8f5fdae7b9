"""External mode against a real Mosquitto: the platform subscribes with its own credentials,
devices (authenticated by the broker) publish telemetry with mosquitto_pub and paho-mqtt,
commands and desired properties reach them through the broker, the platform survives the
broker restarting, and messages sent while the platform was away arrive when it is back."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import orjson
import pytest

from tests.integration._mqtt import (
    Mosquitto,
    MqttPlatform,
    Paho,
    mosquitto_pub,
    mqtt_platform,
    require_mosquitto,
    until,
)
from twinlink.ingest.mqtt import MqttService
from twinlink.ingest.mqtt.client import BrokerRefused

pytestmark = pytest.mark.integration

USERS = {"twinlink": "platform-secret", "rig": "rig-secret"}


@pytest.fixture
async def broker(tmp_path: Path) -> AsyncIterator[Mosquitto]:
    require_mosquitto()
    mosquitto = Mosquitto(tmp_path, USERS)
    await mosquitto.start()
    try:
        yield mosquitto
    finally:
        await mosquitto.stop()


def external(broker: Mosquitto, **overrides: Any) -> dict[str, Any]:
    settings = {"mqtt_mode": "external", "mqtt_broker_url": broker.url,
                "mqtt_username": "twinlink", "mqtt_password": USERS["twinlink"]}  # fmt: skip
    return {**settings, **overrides}


@pytest.fixture
async def platform(tmp_path: Path, broker: Mosquitto) -> AsyncIterator[MqttPlatform]:
    async with mqtt_platform(tmp_path / "data", **external(broker)) as p:
        yield p


async def publish(broker: Mosquitto, topic: str, payload: str, *options: str) -> None:
    rc, out = await mosquitto_pub(broker.port, "-u", "rig", "-P", USERS["rig"], "-q", "1",
                                  "-t", topic, "-m", payload, *options)  # fmt: skip
    assert rc == 0, out


def online(platform: MqttPlatform) -> bool:
    return platform.services.device_hub.session(platform.device.id) is not None


async def test_telemetry_through_the_broker(platform: MqttPlatform, broker: Mosquitto) -> None:
    assert platform.status()["state"] == "connected"
    await publish(broker, platform.topic("telemetry"), '{"angle": 0.25}')
    await publish(broker, platform.topic("telemetry/fast"), '[{"values": {"angle": 1}}]', "-V", "5")
    assert [r["values"] for r in await platform.rows_until(1)] == [{"angle": 0.25}]
    assert [r["values"] for r in await platform.rows_until(1, "fast")] == [{"angle": 1}]
    await until(lambda: online(platform), "the device's session")
    assert platform.status()["clients"] == 1


async def test_commands_and_desired_properties_through_the_broker(
    platform: MqttPlatform, broker: Mosquitto
) -> None:
    device = Paho(broker.port, "rig", USERS["rig"], 5, client_id="rig-1")
    await device.connect()
    try:
        await device.subscribe(platform.topic("commands/+"))
        # A device that only listens announces itself (retained, with `offline` as its will).
        await device.publish(platform.topic("status"), b"online")
        await until(lambda: online(platform), "the device's session")
        command = platform.services.commands.send(
            platform.admin, platform.slug, "set_rate", {"value": 2}, device="rig", timeout_s=10
        )

        sent = asyncio.create_task(command)
        topic, payload = await device.message()
        assert orjson.loads(payload)["args"] == {"value": 2}
        await device.publish(f"{topic}/result", b'{"result": "ok"}')
        done = await sent
        assert (done.state, done.result) == ("succeeded", "ok")
        # Desired values are retained at the broker: a device subscribing later gets them.
        await platform.services.properties.set_desired(
            platform.admin, platform.slug, "rig", {"mode": "fast"}
        )
        await device.subscribe(platform.topic("properties/desired"))
        # The retained one first: that of the session's start (version 0) if the broker has
        # not yet taken the newer one, which then follows.
        desired = orjson.loads((await device.message())[1])
        if desired["version"] == 0:
            desired = orjson.loads((await device.message())[1])
        assert desired == {"properties": {"mode": "fast"}, "version": 1}
        await device.publish(platform.topic("status"), b"offline")
        await until(lambda: not online(platform), "the session to end")
    finally:
        await device.stop()


async def test_unknown_devices_are_counted(platform: MqttPlatform, broker: Mosquitto) -> None:
    await publish(broker, f"twinlink/{platform.slug}/ghost/telemetry", '{"angle": 1}')
    await until(lambda: platform.status()["errors"].get("unknown_device") == 1, "the count")
    assert await platform.rows() == []


async def test_wrong_platform_credentials_are_a_clear_error(
    tmp_path: Path, broker: Mosquitto
) -> None:
    with pytest.raises(BrokerRefused, match="TWINLINK_MQTT_USERNAME"):
        async with mqtt_platform(tmp_path / "data", **external(broker, mqtt_password="wrong")):
            pass


async def test_the_platform_reconnects_when_the_broker_restarts(
    platform: MqttPlatform, broker: Mosquitto
) -> None:
    await broker.stop()
    await until(lambda: platform.status()["state"] == "reconnecting", "the loss to be seen")
    await broker.start()
    await until(lambda: platform.status()["state"] == "connected", "the reconnection")
    await publish(broker, platform.topic("telemetry"), '{"angle": 3}')
    assert [r["values"] for r in await platform.rows_until(1)] == [{"angle": 3}]
    assert platform.status()["connects"] == 2


async def test_messages_sent_while_the_platform_was_away_arrive(
    platform: MqttPlatform, broker: Mosquitto
) -> None:
    await platform.mqtt.close()
    await publish(broker, platform.topic("telemetry"), '{"angle": 7}')  # QoS 1, kept for it
    again = MqttService(
        platform.settings, platform.services.devices, platform.services.device_hub,
        platform.services.ingest,
    )  # fmt: skip
    platform.mqtt = again  # what platform.status() reads
    try:
        await again.open()
        assert [r["values"] for r in await platform.rows_until(1)] == [{"angle": 7}]
    finally:  # the fixture stops the platform's own MQTT service, closed above, not this one
        await again.close()
