"""The state and the errors every device transport shows (the MQTT service, each connector):
one state with the time it was entered, errors counted by kind, the last one's text."""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

MAX_ERROR_TEXT = 500


@dataclass(slots=True, kw_only=True)
class Health:
    state: str = "stopped"
    since_ns: int = field(default_factory=time.time_ns)
    errors: Counter[str] = field(default_factory=Counter)
    last_error: str | None = None
    last_error_ns: int | None = None

    def set_state(self, state: str) -> None:
        if state != self.state:
            self.state = state
            self.since_ns = time.time_ns()

    def error(self, kind: str, text: str) -> None:
        """Count an error of `kind` (a short name: malformed, truncated, unknown_topic, ...)
        and keep its text as the last error."""
        self.errors[kind] += 1
        self.last_error = f"{kind}: {text}"[:MAX_ERROR_TEXT]
        self.last_error_ns = time.time_ns()

    def health_view(self) -> dict[str, Any]:
        return {
            "state": self.state,
            "since_ns": self.since_ns,
            "errors": dict(self.errors),
            "error_count": sum(self.errors.values()),
            "last_error": self.last_error,
            "last_error_ns": self.last_error_ns,
        }
