"""What the MQTT service counts: connections, messages by kind, samples, and errors by kind
(shown by the status view and, through the lead's wiring, metrics)."""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

MAX_ERROR_TEXT = 500


@dataclass(slots=True)
class MqttStatus:
    """`state`: stopped, listening (embedded), connecting, connected, reconnecting (external)."""

    mode: str
    address: str = ""
    state: str = "stopped"
    since_ns: int = field(default_factory=time.time_ns)
    clients: int = 0  # embedded: open connections; external: device sessions
    connects: int = 0
    refused: Counter[str] = field(default_factory=Counter)
    received: Counter[str] = field(default_factory=Counter)  # messages by kind
    samples: int = 0
    sent: int = 0  # publishes to devices
    errors: Counter[str] = field(default_factory=Counter)
    last_error: str | None = None
    last_error_ns: int | None = None

    def set_state(self, state: str) -> None:
        if state != self.state:
            self.state = state
            self.since_ns = time.time_ns()

    def error(self, kind: str, text: str) -> None:
        """Count an error of `kind` (malformed, unknown_topic, refused_batch, ...)."""
        self.errors[kind] += 1
        self.last_error = f"{kind}: {text}"[:MAX_ERROR_TEXT]
        self.last_error_ns = time.time_ns()

    def view(self) -> dict[str, Any]:
        return {
            "mode": self.mode,
            "address": self.address,
            "state": self.state,
            "since_ns": self.since_ns,
            "clients": self.clients,
            "connects": self.connects,
            "refused": dict(self.refused),
            "messages": sum(self.received.values()),
            "received": dict(self.received),
            "samples": self.samples,
            "sent": self.sent,
            "errors": dict(self.errors),
            "error_count": sum(self.errors.values()),
            "last_error": self.last_error,
            "last_error_ns": self.last_error_ns,
        }
