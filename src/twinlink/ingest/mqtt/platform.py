"""What the MQTT service needs of the platform, in one place (built by `app.py`)."""

from __future__ import annotations

from dataclasses import dataclass

from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub
from twinlink.registry.devices import DeviceService

MAX_MESSAGE_BYTES = 16 * 1024 * 1024 + 64 * 1024  # a 16 MiB batch plus topic and headers


@dataclass(frozen=True, slots=True)
class Platform:
    devices: DeviceService
    hub: DeviceHub
    ingest: IngestService
