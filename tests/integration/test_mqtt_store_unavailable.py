"""An MQTT device that connects while the store cannot be read (PostgreSQL restarting, say):
its token could not be checked, which is not a bad token. The CONNACK says the server is
unavailable (MQTT 5 reason 136, 3.1.1 code 3), so the client retries instead of giving up on
its credentials (docs/decisions/0013-acknowledgement-in-scale-out.md)."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from tests.integration._mqtt import MqttPlatform, Paho, mqtt_platform
from twinlink.domain.errors import StorageError
from twinlink.domain.records import Device
from twinlink.ingest.mqtt import packets as mq

pytestmark = pytest.mark.integration


@pytest.fixture
async def platform(tmp_path: Path) -> AsyncIterator[MqttPlatform]:
    async with mqtt_platform(tmp_path / "data") as p:
        yield p


@pytest.mark.parametrize("version", [4, 5])
async def test_a_token_that_cannot_be_checked_is_server_unavailable(
    platform: MqttPlatform, version: int
) -> None:
    async def unreadable(token: str) -> Device:
        raise StorageError("The server's database (PostgreSQL) cannot be reached. Retry later.")

    platform.services.devices.authenticate = unreadable  # type: ignore[method-assign]
    device = Paho(platform.port, "rig", platform.token, version)
    try:
        reason = await device.connect()
    finally:
        await device.stop()
    assert reason.value == mq.SERVER_UNAVAILABLE, reason  # paho reads 3.1.1's code 3 as 136
    assert platform.status()["refused"] == {"other": 1}  # not counted as a bad token
