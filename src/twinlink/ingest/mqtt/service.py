"""MQTT device connectivity (docs/mqtt.md), in the mode the settings choose:

- `embedded` (default): `twinlink up` listens for MQTT itself (`EmbeddedListener`);
- `external`: the platform is a client of a broker the user runs (`ExternalBroker`);
- `off`: no MQTT.
"""

from __future__ import annotations

from typing import Any, Protocol

from twinlink.config import Settings
from twinlink.ingest.mqtt.external import ExternalBroker
from twinlink.ingest.mqtt.leased import LeasedBroker
from twinlink.ingest.mqtt.listener import EmbeddedListener
from twinlink.ingest.mqtt.platform import MAX_MESSAGE_BYTES, Platform
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import TopicScheme
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub
from twinlink.registry.devices import DeviceService
from twinlink.store.leases import Claims


class _Mode(Protocol):
    async def open(self) -> None: ...

    async def close(self) -> None: ...


class MqttService:
    """`await open()` at start (raises ListenerError or BrokerError with a message that names
    the setting to change), `await close()` at stop, `view()` for status."""

    def __init__(
        self,
        settings: Settings,
        devices: DeviceService,
        hub: DeviceHub,
        ingest: IngestService,
        claims: Claims | None = None,
    ) -> None:
        """`claims`: on a store shared by several nodes, the lease that lets one node hold the
        external broker's session (ingest/mqtt/leased.py)."""
        self.status = MqttStatus(settings.mqtt_mode)
        platform = Platform(devices, hub, ingest)
        scheme = TopicScheme(settings.mqtt_topic_prefix)
        self.listener: EmbeddedListener | None = None
        self.broker: ExternalBroker | None = None
        self._mode: _Mode | None = None
        if settings.mqtt_mode == "embedded":
            self.listener = EmbeddedListener(
                platform, settings.mqtt_host, settings.mqtt_port, scheme, self.status,
                MAX_MESSAGE_BYTES, reuse_port=settings.workers > 1,
            )  # fmt: skip
            self._mode = self.listener
        elif settings.mqtt_mode == "external":
            password = settings.mqtt_password
            self.broker = ExternalBroker(
                platform,
                settings.mqtt_broker_url,
                settings.mqtt_username,
                password.get_secret_value() if password is not None else None,
                settings.mqtt_client_id,
                scheme,
                self.status,
            )
            self._mode = self.broker
            if claims is not None:
                self._mode = LeasedBroker(self.broker, claims, self.status)

    async def open(self) -> None:
        if self._mode is not None:
            await self._mode.open()

    async def close(self) -> None:
        if self._mode is not None:
            await self._mode.close()

    @property
    def port(self) -> int | None:
        """The port the embedded listener got (useful with port 0)."""
        return self.listener.port if self.listener is not None else None

    def view(self) -> dict[str, Any]:
        return self.status.view()
