"""A command and its states: pending -> delivered -> succeeded | failed, or expired.

Transitions return whether they changed anything, so a repeated `delivered` or `result` from a
device (it may resend after a reconnect) is harmless. A result that comes after the command
expired is kept (`result`, `error`, `late_status`) but the state stays `expired`: whoever was
waiting has already been told.
"""

from __future__ import annotations

import base64
import secrets
from dataclasses import dataclass
from typing import Any, Literal

from twinlink.registry.build import human_time, human_time_or_none

State = Literal["pending", "delivered", "succeeded", "failed", "expired"]
STATES: tuple[State, ...] = ("pending", "delivered", "succeeded", "failed", "expired")
OPEN_STATES = frozenset({"pending", "delivered"})
OFFLINE = "device offline"


_ID_BYTES = 12
_random = bytearray()


def new_command_id() -> str:
    """96 random bits, URL-safe: short, and not guessable from other ids. The bytes come from
    the OS generator a few kilobytes at a time, not one system call per command."""
    global _random
    if not _random:
        _random = bytearray(secrets.token_bytes(_ID_BYTES * 256))
    chunk = bytes(_random[-_ID_BYTES:])
    del _random[-_ID_BYTES:]
    return base64.urlsafe_b64encode(chunk).decode()


@dataclass(slots=True)
class CommandRecord:
    id: str
    twin_id: int
    device_id: int
    device: str
    name: str
    args: dict[str, Any]
    state: State
    queued: bool
    sent_by: str | None
    created_ns: int
    expires_ns: int
    delivered_ns: int | None = None
    finished_ns: int | None = None
    result: Any = None
    error: str | None = None
    late_status: str | None = None

    @property
    def is_open(self) -> bool:
        return self.state in OPEN_STATES

    def deliver(self, now_ns: int) -> bool:
        if self.state != "pending":
            return False
        self.state = "delivered"
        self.delivered_ns = now_ns
        return True

    def finish(self, status: str, result: Any, error: str | None, now_ns: int) -> bool:
        """The device's result. After expiry it is recorded as late; a second result is ignored."""
        if status not in ("succeeded", "failed"):
            raise ValueError("`status` must be succeeded or failed")
        if self.state == "expired" and self.late_status is None:
            self.late_status = status
            self.result, self.error = result, error
            return True
        if not self.is_open:
            return False
        self.state = "succeeded" if status == "succeeded" else "failed"
        self.result, self.error = result, error
        self.finished_ns = now_ns
        if self.delivered_ns is None:  # a result implies delivery
            self.delivered_ns = now_ns
        return True

    def fail(self, error: str, now_ns: int) -> bool:
        """Failed by the platform (the device is offline), not by the device."""
        if not self.is_open:
            return False
        self.state = "failed"
        self.error = error
        self.finished_ns = now_ns
        return True

    def expire(self, now_ns: int) -> bool:
        if not self.is_open:
            return False
        self.state = "expired"
        self.finished_ns = now_ns
        return True

    def message(self) -> dict[str, Any]:
        """The `command` message for the device (docs/protocol.md)."""
        return {
            "type": "command",
            "id": self.id,
            "name": self.name,
            "args": self.args,
            "expires": self.expires_ns,
        }

    def view(self, twin_slug: str) -> dict[str, Any]:
        """The command as the API shows it."""
        return {
            "id": self.id,
            "twin": twin_slug,
            "device": self.device,
            "name": self.name,
            "args": self.args,
            "state": self.state,
            "queued": self.queued,
            "sent_by": self.sent_by,
            "created": human_time(self.created_ns),
            "expires": human_time(self.expires_ns),
            "delivered": human_time_or_none(self.delivered_ns),
            "finished": human_time_or_none(self.finished_ns),
            "result": self.result,
            "error": self.error,
            "late_status": self.late_status,
        }
