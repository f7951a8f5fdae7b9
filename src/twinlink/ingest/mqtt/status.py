"""What the MQTT service counts: connections, messages by kind, samples, and errors by kind
(shown by the status view and, through the lead's wiring, metrics)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any

from twinlink.ingest.health import Health


@dataclass(slots=True)
class MqttStatus(Health):
    """`state`: stopped, listening (embedded), connecting, connected, reconnecting (external)."""

    mode: str
    address: str = ""
    clients: int = 0  # embedded: open connections; external: device sessions
    connects: int = 0
    refused: Counter[str] = field(default_factory=Counter)
    received: Counter[str] = field(default_factory=Counter)  # messages by kind
    samples: int = 0
    sent: int = 0  # publishes to devices

    def view(self) -> dict[str, Any]:
        return {
            **self.health_view(),
            "mode": self.mode,
            "address": self.address,
            "clients": self.clients,
            "connects": self.connects,
            "refused": dict(self.refused),
            "messages": sum(self.received.values()),
            "received": dict(self.received),
            "samples": self.samples,
            "sent": self.sent,
        }
