"""Commands and properties over the embedded MQTT listener: a command reaches the device's
`commands/{id}` topic (also one sent just before it subscribed, and a queued one sent while
it was offline), its result is recorded; desired properties arrive on `properties/desired`
(the current delta as soon as the device subscribes), reported ones are stored and
answered."""

from __future__ import annotations

import asyncio
import subprocess
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
from twinlink.domain.commands import CommandRecord
from twinlink.ingest.mqtt import packets as mq

pytestmark = pytest.mark.integration


@pytest.fixture
async def platform(tmp_path: Path) -> AsyncIterator[MqttPlatform]:
    require_mosquitto()
    async with mqtt_platform(tmp_path / "data") as p:
        yield p


def online(platform: MqttPlatform) -> bool:
    return platform.services.device_hub.session(platform.device.id) is not None


async def send(platform: MqttPlatform, name: str, **kwargs: Any) -> CommandRecord:
    commands = platform.services.commands
    return await commands.send(platform.admin, platform.slug, name, device="rig", **kwargs)


@pytest.mark.parametrize("version", [4, 5])
async def test_paho_device_runs_a_command(platform: MqttPlatform, version: int) -> None:
    device = Paho(platform.port, "rig", platform.token, version)
    await device.connect()
    try:
        assert await device.subscribe(platform.topic("commands/+")) == [1]
        sent = asyncio.create_task(send(platform, "set_rate", args={"value": 5}))
        topic, payload = await device.message()
        command = orjson.loads(payload)
        assert topic == platform.topic(f"commands/{command['id']}")
        assert (command["name"], command["args"]) == ("set_rate", {"value": 5})
        await device.publish(f"{topic}/delivered", b"")
        await device.publish(f"{topic}/result", b'{"result": {"rate": 5}}')
        record = await sent
    finally:
        await device.stop()
    assert (record.state, record.result, record.delivered_ns is not None) == (
        "succeeded", {"rate": 5}, True,
    )  # fmt: skip
    assert platform.status()["received"] == {"delivered": 1, "result": 1}


async def test_mosquitto_sub_and_pub_answer_a_command(platform: MqttPlatform) -> None:
    sub = await asyncio.create_subprocess_exec(
        "mosquitto_sub", "-p", str(platform.port), "-u", "rig", "-P", platform.token,
        "-t", platform.topic("commands/+"), "-C", "1", "-v", stdout=subprocess.PIPE,
    )  # fmt: skip
    try:
        # Sent as soon as the device is connected, maybe before it subscribed: held until then.
        await until(lambda: online(platform), "mosquitto_sub to connect")
        sent = asyncio.create_task(send(platform, "pause"))
        assert sub.stdout is not None
        async with asyncio.timeout(10):
            line = (await sub.stdout.readline()).decode()
        topic, payload = line.split(" ", 1)
        assert orjson.loads(payload)["name"] == "pause"
        rc, out = await mosquitto_pub(
            platform.port, "-u", "rig", "-P", platform.token, "-q", "1",
            "-t", f"{topic}/result", "-m", '{"status": "failed", "error": "jammed"}',
        )  # fmt: skip
        assert rc == 0, out
        record = await sent
    finally:
        if sub.returncode is None:
            sub.kill()
        await sub.wait()
    assert (record.state, record.error) == ("failed", "jammed")


async def test_a_queued_command_reaches_the_device_when_it_connects(
    platform: MqttPlatform,
) -> None:
    record = await send(platform, "pause", queue=True, wait=False)
    assert record.state == "pending"
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await device.subscribe(platform.topic("commands/#"))
        topic, payload = await device.message()
        assert orjson.loads(payload)["id"] == record.id
        await device.publish(f"{topic}/result", b"")
        stored = await platform.services.commands.get(platform.admin, platform.slug, record.id)
    finally:
        await device.stop()
    assert stored.state == "succeeded"


async def test_a_result_for_an_unknown_command_is_told(platform: MqttPlatform) -> None:
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await device.subscribe(platform.topic("errors"))
        await device.publish(platform.topic("commands/nosuchcommand/result"), b"{}")
        error = orjson.loads((await device.message())[1])
    finally:
        await device.stop()
    assert (error["op"], error["id"]) == ("result", "nosuchcommand")
    assert platform.status()["errors"] == {"refused_result": 1}


async def test_desired_and_reported_properties(platform: MqttPlatform) -> None:
    properties = platform.services.properties
    await properties.set_desired(platform.admin, platform.slug, "rig", {"sample_rate": 50})
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await device.subscribe(platform.topic("acks"))
        # On subscribing, the device gets what it should change (the delta) at once.
        await device.subscribe(platform.topic("properties/desired"))
        topic, payload = await device.message()
        assert topic == platform.topic("properties/desired")
        assert orjson.loads(payload) == {"properties": {"sample_rate": 50}, "version": 1}
        reason = await device.publish(platform.topic("properties/reported"), b'{"sample_rate": 50}')
        assert reason == 0
        assert orjson.loads((await device.message())[1]) == {
            "type": "reported_ack", "version": 1, "desired": {},
        }  # fmt: skip
        await properties.set_desired(platform.admin, platform.slug, "rig", {"mode": "fast"})
        topic, payload = await device.message()
        assert orjson.loads(payload) == {"properties": {"mode": "fast"}, "version": 2}
    finally:
        await device.stop()
    shown = await properties.show(platform.admin, platform.slug, "rig")
    assert shown.reported["sample_rate"][0] == 50


async def test_reported_with_mosquitto_pub_and_a_refused_report(platform: MqttPlatform) -> None:
    rc, out = await mosquitto_pub(
        platform.port, "-u", "rig", "-P", platform.token, "-q", "1",
        "-t", platform.topic("properties/reported"), "-m", '{"mode": "slow"}',
    )  # fmt: skip
    assert rc == 0, out
    shown = await platform.services.properties.show(platform.admin, platform.slug, "rig")
    assert shown.reported["mode"][0] == "slow"  # stored before the PUBACK
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        await device.subscribe(platform.topic("errors"))
        reason = await device.publish(platform.topic("properties/reported"), b'{"colour": 1}')
        assert reason == mq.PAYLOAD_FORMAT_INVALID
        error = orjson.loads((await device.message())[1])
    finally:
        await device.stop()
    assert error["op"] == "reported" and "colour" in error["message"] and "id" not in error


async def test_subscriptions_outside_the_device_are_refused(platform: MqttPlatform) -> None:
    device = Paho(platform.port, "rig", platform.token, 5)
    await device.connect()
    try:
        codes = await device.subscribe(f"twinlink/{platform.slug}/other/commands/+")
        assert codes == [mq.NOT_AUTHORIZED]
        assert await device.subscribe("twinlink/+/+/errors") == [1]
    finally:
        await device.stop()
    assert platform.status()["errors"] == {"subscribe_refused": 1}
