"""The topic scheme (docs/mqtt.md): `{prefix}/{twin}/{device}/...`, one tree per device, the
same in the embedded and the external mode, short enough to type with `mosquitto_pub`.

Device to platform: `telemetry`, `telemetry/{stream}`, `commands/{id}/delivered`,
`commands/{id}/result`, `properties/reported`, `status`. Platform to device: `commands/{id}`,
`properties/desired`, `acks`, `errors`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.slug import SLUG
from twinlink.registry.devices import DEVICE_NAME

STREAM = re.compile(r"^[a-z][a-z0-9_-]{0,63}$")
COMMAND_ID = re.compile(r"^[A-Za-z0-9_-]{1,64}$")

TELEMETRY = "telemetry"
DELIVERED = "delivered"
RESULT = "result"
REPORTED = "reported"
STATUS = "status"


class TopicError(TwinlinkError, ValueError):
    """A topic outside the scheme; the message says what was expected."""


@dataclass(frozen=True, slots=True)
class Route:
    """Where a device's message goes: its twin and device, what it is (`kind`), and the
    stream (telemetry) or command id (delivered, result) the topic names."""

    twin: str
    device: str
    kind: str
    detail: str | None = None


class TopicScheme:
    """The topics under one prefix (`twinlink` by default; it may hold `/`)."""

    def __init__(self, prefix: str) -> None:
        self.prefix = prefix.strip("/")
        self._depth = len(self.prefix.split("/"))

    def base(self, twin: str, device: str) -> str:
        return f"{self.prefix}/{twin}/{device}"

    def route(self, topic: str) -> Route:
        """The route of a topic a device published to; TopicError when it is not one."""
        levels = topic.split("/")
        if levels[: self._depth] != self.prefix.split("/"):
            raise TopicError(f"topics start with {self.prefix}/{{twin}}/{{device}}/")
        rest = levels[self._depth :]
        if len(rest) < 3:
            raise TopicError(f"{topic!r}: expected {self.prefix}/{{twin}}/{{device}}/telemetry")
        twin, device, *path = rest
        if not SLUG.match(twin) or not DEVICE_NAME.match(device):
            raise TopicError(f"{topic!r}: {twin!r} is not a twin slug or {device!r} a device name")
        return Route(twin, device, *_kind(path, topic))

    def subscriptions(self) -> list[str]:
        """The filters that take every device's messages (external mode)."""
        p = self.prefix
        return [
            f"{p}/+/+/telemetry",
            f"{p}/+/+/telemetry/+",
            f"{p}/+/+/commands/+/delivered",
            f"{p}/+/+/commands/+/result",
            f"{p}/+/+/properties/reported",
            f"{p}/+/+/status",
        ]


def _kind(path: list[str], topic: str) -> tuple[str, str | None]:
    match path:
        case ["telemetry"]:
            return TELEMETRY, None
        case ["telemetry", stream]:
            if not STREAM.match(stream):
                raise TopicError(f"{topic!r}: a stream name matches {STREAM.pattern}")
            return TELEMETRY, stream
        case ["commands", command_id, ("delivered" | "result") as what]:
            if not COMMAND_ID.match(command_id):
                raise TopicError(f"{topic!r}: {command_id!r} is not a command id")
            return what, command_id
        case ["properties", "reported"]:
            return REPORTED, None
        case ["status"]:
            return STATUS, None
    known = "telemetry[/{stream}], commands/{id}/delivered, commands/{id}/result, "
    raise TopicError(f"{topic!r}: a device publishes to {known}properties/reported or status")


class DeviceTopics:
    """The topics of one device, and which of them a subscription filter reaches."""

    def __init__(self, scheme: TopicScheme, twin: str, device: str) -> None:
        self.base = scheme.base(twin, device)
        self.desired = f"{self.base}/properties/desired"
        self.acks = f"{self.base}/acks"
        self.errors = f"{self.base}/errors"
        # What the platform publishes to the device; `\0` stands for any command id.
        self._outgoing = [f"{self.base}/commands/\0", self.desired, self.acks, self.errors]

    def command(self, command_id: str) -> str:
        return f"{self.base}/commands/{command_id}"

    def reachable(self, topic_filter: str) -> bool:
        """True when the filter matches at least one topic the platform sends this device."""
        levels = topic_filter.split("/")
        return any(matches(levels, topic.split("/")) for topic in self._outgoing)


def valid_filter(topic_filter: str) -> bool:
    """A topic filter as MQTT allows it (4.7.1): `#` only last and alone in its level, `+`
    alone in its level."""
    if not topic_filter:
        return False
    levels = topic_filter.split("/")
    for i, level in enumerate(levels):
        if "#" in level and (level != "#" or i != len(levels) - 1):
            return False
        if "+" in level and level != "+":
            return False
    return True


def matches(filter_levels: list[str], topic_levels: list[str]) -> bool:
    """Whether a filter (split at `/`) matches a topic; a topic level `\\0` is any name."""
    for i, level in enumerate(filter_levels):
        if level == "#":
            return True
        if i >= len(topic_levels):
            return False
        if level != "+" and level != topic_levels[i] and topic_levels[i] != "\0":
            return False
    return len(filter_levels) == len(topic_levels)
