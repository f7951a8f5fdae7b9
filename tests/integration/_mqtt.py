"""Helpers of the MQTT integration tests: a real platform built in-process with its MQTT
service, real clients (paho-mqtt in its own thread, mosquitto_pub/mosquitto_sub as
processes), and a real Mosquitto broker for the external mode."""

from __future__ import annotations

import asyncio
import queue
import shutil
import subprocess
import threading
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import paho.mqtt.client as paho
import pytest
from paho.mqtt.enums import CallbackAPIVersion
from paho.mqtt.reasoncodes import ReasonCode

from tests.conftest import free_port
from twinlink.app import Services, build_services, start_services, stop_services
from twinlink.auth.rights import Principal
from twinlink.config import Settings
from twinlink.domain.errors import NotFoundError
from twinlink.domain.records import Device
from twinlink.domain.yamlsource import SourceDocument
from twinlink.ingest.mqtt import MqttService

WAIT_S = 10.0
MIN_TIME, MAX_TIME = -(2**63), 2**63 - 1
INTERFACE = {
    "signals": [{"name": "angle", "type": "number"}, {"name": "force", "type": "number"}],
    "properties": [{"name": "sample_rate", "type": "number", "writable": True},
                   {"name": "mode", "type": "string", "writable": True}],
    "commands": [{"name": "pause"}, {"name": "set_rate", "parameters": [
        {"name": "value", "type": "number"}]}],
}  # fmt: skip


def require_mosquitto() -> None:
    """The tests use the real Mosquitto tools; `make test` installs them."""
    missing = [t for t in ("mosquitto", "mosquitto_pub", "mosquitto_sub") if not shutil.which(t)]
    if missing:
        pytest.fail(
            f"{', '.join(missing)} not found: install the Debian packages mosquitto and "
            "mosquitto-clients (make test does: scripts/ensure-packages.sh)"
        )


async def until(condition: Callable[[], bool], what: str = "the condition") -> None:
    """Wait until `condition` holds (changed by the event loop or a client thread)."""
    try:
        async with asyncio.timeout(WAIT_S):
            while not condition():
                await asyncio.sleep(0.002)
    except TimeoutError:
        raise AssertionError(f"timed out waiting for {what}") from None


@dataclass
class MqttPlatform:
    services: Services
    settings: Settings
    mqtt: MqttService
    admin: Principal
    slug: str
    device: Device
    token: str

    @property
    def port(self) -> int:
        assert self.mqtt.port is not None
        return self.mqtt.port

    def topic(self, suffix: str, device: str | None = None) -> str:
        return f"twinlink/{self.slug}/{device or self.device.name}/{suffix}"

    async def add_device(self, name: str) -> tuple[Device, str]:
        return await self.services.devices.create(self.admin, self.slug, name, "")

    async def rows(self, stream: str = "telemetry") -> list[dict[str, Any]]:
        """The stored samples of a stream ([] before the stream has any)."""
        try:
            page = await self.services.history.samples(
                self.device.twin_id, stream, None, MIN_TIME, MAX_TIME, 100_000
            )
        except NotFoundError:
            return []
        return page.rows

    async def rows_until(self, count: int, stream: str = "telemetry") -> list[dict[str, Any]]:
        """The stored samples once there are `count` of them."""
        async with asyncio.timeout(WAIT_S):
            while len(rows := await self.rows(stream)) < count:
                await asyncio.sleep(0.005)
        return rows

    def status(self) -> dict[str, Any]:
        return self.mqtt.view()


@asynccontextmanager
async def mqtt_platform(data_dir: Path, **mqtt: Any) -> AsyncIterator[MqttPlatform]:
    """A platform with a twin (with an interface), its device `rig` and the MQTT service."""
    settings = Settings(data_dir=data_dir, history_sync="normal", **{"mqtt_port": 0, **mqtt})
    services = build_services(settings)
    await start_services(services, settings)
    service = services.mqtt  # the app's own, opened by start_services
    try:
        admin_user = await services.store.get_user_by_name("admin")
        assert admin_user is not None
        admin = Principal(admin_user)
        doc = {"version": "1.0", "privacy": "public", "id": "urn:rig", "interface": INTERFACE}
        [applied] = await services.registry.apply(admin, [SourceDocument(doc)])
        device, token = await services.devices.create(admin, applied.twin.slug, "rig", "")
        yield MqttPlatform(services, settings, service, admin, applied.twin.slug, device, token)
    finally:
        await stop_services(services)


@dataclass
class Paho:
    """A paho-mqtt client in its own network thread; the test reads what it saw."""

    port: int
    username: str | None
    password: str | None
    version: int = 5
    client_id: str = ""
    inbox: queue.Queue[tuple[str, bytes]] = field(default_factory=queue.Queue)
    acks: dict[int, int] = field(default_factory=dict)  # mid -> PUBACK reason code
    subacks: dict[int, list[int]] = field(default_factory=dict)
    connack: ReasonCode | None = None
    disconnect_reason: ReasonCode | None = None
    connected: threading.Event = field(default_factory=threading.Event)
    disconnected: threading.Event = field(default_factory=threading.Event)

    def __post_init__(self) -> None:
        protocol = paho.MQTTv5 if self.version == 5 else paho.MQTTv311
        self.client = paho.Client(
            CallbackAPIVersion.VERSION2, client_id=self.client_id, protocol=protocol
        )
        if self.username is not None:
            self.client.username_pw_set(self.username, self.password)
        self.client.on_connect = self._on_connect
        self.client.on_message = lambda c, u, m: self.inbox.put((m.topic, bytes(m.payload)))
        self.client.on_publish = self._on_publish
        self.client.on_subscribe = self._on_subscribe
        self.client.on_disconnect = self._on_disconnect

    def _on_connect(self, c: Any, u: Any, flags: Any, reason: ReasonCode, props: Any) -> None:
        self.connack = reason
        self.connected.set()

    def _on_publish(self, c: Any, u: Any, mid: int, reason: ReasonCode, props: Any) -> None:
        self.acks[mid] = reason.value

    def _on_subscribe(self, c: Any, u: Any, mid: int, codes: list[ReasonCode], p: Any) -> None:
        self.subacks[mid] = [code.value for code in codes]

    def _on_disconnect(self, c: Any, u: Any, f: Any, reason: ReasonCode, p: Any) -> None:
        self.disconnect_reason = reason
        self.disconnected.set()

    async def connect(self) -> ReasonCode:
        """Connect and wait for the CONNACK; a refused client stops (no retries)."""
        self.connected.clear()
        self.client.connect("127.0.0.1", self.port, keepalive=60)
        self.client.loop_start()
        assert await asyncio.to_thread(self.connected.wait, WAIT_S), "no CONNACK"
        assert self.connack is not None
        if self.connack.is_failure:
            await self.stop()
        return self.connack

    async def subscribe(self, topic: str, qos: int = 1) -> list[int]:
        _, mid = self.client.subscribe(topic, qos)
        assert mid is not None
        await until(lambda: mid in self.subacks, f"the SUBACK of {topic}")
        return self.subacks[mid]

    async def publish(self, topic: str, payload: bytes | str, qos: int = 1) -> int:
        """Publish and wait until it is acknowledged; the PUBACK's reason (MQTT 5)."""
        info = self.client.publish(topic, payload, qos)
        if qos == 0:
            return 0
        await until(lambda: info.mid in self.acks, f"the PUBACK of {topic}")
        return self.acks[info.mid]

    async def message(self) -> tuple[str, bytes]:
        return await asyncio.to_thread(self.inbox.get, True, WAIT_S)

    async def stop(self) -> None:
        self.client.disconnect()
        await asyncio.to_thread(self.client.loop_stop)


async def run(*command: str, timeout: float = WAIT_S) -> tuple[int, str]:
    """Run a Mosquitto tool; its exit status and what it printed (stdout and stderr)."""
    process = await asyncio.create_subprocess_exec(
        *command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT
    )
    async with asyncio.timeout(timeout):
        out, _ = await process.communicate()
    assert process.returncode is not None
    return process.returncode, out.decode()


async def mosquitto_pub(port: int, *args: str) -> tuple[int, str]:
    return await run("mosquitto_pub", "-h", "127.0.0.1", "-p", str(port), *args)


@dataclass
class Mosquitto:
    """A real Mosquitto broker on a free loopback port, with users from a password file."""

    folder: Path
    users: dict[str, str]
    port: int = field(default_factory=free_port)
    process: subprocess.Popen[bytes] | None = None

    async def start(self) -> None:
        passwd = self.folder / "passwd"
        passwd.write_text("".join(f"{user}:{password}\n" for user, password in self.users.items()))
        rc, out = await run("mosquitto_passwd", "-U", str(passwd))  # hashes the passwords
        assert rc == 0, out
        config = self.folder / "mosquitto.conf"
        # `user root`: started as root (CI), Mosquitto would switch to the user `mosquitto`,
        # who cannot read the test's folder; as anyone else the line has no effect.
        config.write_text(
            f"listener {self.port} 127.0.0.1\nallow_anonymous false\n"
            f"password_file {passwd}\npersistence false\nlog_dest stderr\nuser root\n"
        )
        with (self.folder / "mosquitto.log").open("ab") as log:
            self.process = subprocess.Popen(
                ["mosquitto", "-c", str(config)], stdout=subprocess.DEVNULL, stderr=log
            )
        async with asyncio.timeout(WAIT_S):
            while not await self._accepts():
                assert self.process.poll() is None, (self.folder / "mosquitto.log").read_text()
                await asyncio.sleep(0.01)

    async def _accepts(self) -> bool:
        try:
            _, writer = await asyncio.open_connection("127.0.0.1", self.port)
        except OSError:
            return False
        writer.close()
        await writer.wait_closed()
        return True

    async def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            await asyncio.to_thread(self.process.wait, WAIT_S)
        self.process = None

    @property
    def url(self) -> str:
        return f"mqtt://127.0.0.1:{self.port}"
