"""A stand-in for the `digitalTwinPlt` module of the NTNU thesis, so its device code runs on
twinlink with only its import line changed:

```python
import twinlink_edge.compat as digitalTwinPlt          # was: import digitalTwinPlt
from twinlink_edge.compat import Connect                # was: from digitalTwinPlt import Connect

dtMessaging = Connect(device_id="test_device", topic="0000")
dtMessaging.add_to_message(name="Temperature", value=20)
dtMessaging.send()
for topic, partition_msg in dtMessaging.receive().items():
    for m in partition_msg:
        if m.value == b"pause":
            ...
```

The server URL and the device token come from `TWINLINK_URL` and `TWINLINK_DEVICE_TOKEN`, or
from the `url` and `token` arguments. The token names the device: `device_id` is only checked
against it (a warning when they differ). `topic` is the key of what `receive()` returns; the
samples go to the stream `stream` (default `telemetry`)."""

from __future__ import annotations

import logging
import os
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from typing import Any

from ._protocol import JsonObject, dumps
from .sync import Device

__all__ = ["Connect", "Message"]

log = logging.getLogger("twinlink_edge")

IDLE_WAIT = 0.05  # seconds an idle receive() waits, so a polling loop does not spin


@dataclass(frozen=True)
class Message:
    """A received command, shaped like the Kafka record the thesis's code reads: `value` is
    the command name as bytes (`b"pause"`), or when it has arguments the JSON of
    `{"name": ..., "args": {...}}`."""

    topic: str
    partition: int
    offset: int
    timestamp: int  # milliseconds since the epoch, when it arrived
    key: bytes | None
    value: bytes
    name: str = ""
    args: JsonObject = field(default_factory=dict)


class Connect:
    """The thesis's `Connect`: `add_to_message` sets values in the pending message, `send`
    sends it as one sample stamped with the device clock (the values stay for the next
    message; later calls update them), `receive` returns the commands that arrived since the
    last call as `{topic: [Message, ...]}` (each command is answered `succeeded` at once)."""

    def __init__(
        self,
        device_id: str | None = None,
        topic: str = "telemetry",
        receiving_partition: int = 0,
        *,
        url: str | None = None,
        token: str | None = None,
        stream: str = "telemetry",
        flush_interval: float = 0.0,
        **options: Any,
    ) -> None:
        url = url or os.environ.get("TWINLINK_URL")
        token = token or os.environ.get("TWINLINK_DEVICE_TOKEN")
        if not url or not token:
            raise ValueError("set TWINLINK_URL and TWINLINK_DEVICE_TOKEN, or pass url= and token=")
        self.device_id = device_id
        self.topic = topic
        self.receiving_partition = receiving_partition
        self.message: dict[str, Any] = {}
        self._inbox: deque[Message] = deque()
        self._cond = threading.Condition()
        self._offset = 0
        self._idle = False  # the last receive() returned nothing
        self._sent = False  # send() was called since the last receive()
        self._checked_id = device_id is None
        self.device = Device(url, token, stream=stream, flush_interval=flush_interval, **options)
        self.device.on_any_command(self._on_command)
        self.device.start()

    def add_to_message(self, name: str, value: Any) -> None:
        """Set `name` in the pending message (a new attribute, or an update of one)."""
        self.message[name] = value

    def send(self) -> None:
        """Send the pending message as one sample, stamped now."""
        self._check_id()
        if not self.message:
            log.warning("send(): the message is empty; add_to_message() first")
            return
        self.device.add(dict(self.message), time.time_ns())
        with self._cond:
            self._sent = True

    def receive(self, timeout_ms: int | None = None) -> dict[str, list[Message]]:
        """The commands received since the last call, as `{topic: [Message, ...]}`, or `{}`.

        Returns at once, except when the previous call also returned nothing and nothing was
        sent in between (a loop waiting for a command): then it waits up to 50 ms for one, so
        such a loop does not spin. `timeout_ms` sets the wait instead."""
        self._check_id()
        with self._cond:
            if not self._inbox:
                if timeout_ms is not None:
                    wait = max(0.0, timeout_ms / 1000)
                else:
                    wait = IDLE_WAIT if self._idle and not self._sent else 0.0
                if wait:
                    self._cond.wait_for(lambda: bool(self._inbox), wait)
            messages = list(self._inbox)
            self._inbox.clear()
            self._idle = not messages
            self._sent = False
        return {self.topic: messages} if messages else {}

    def flush(self, timeout: float | None = None) -> None:
        """Wait until every message sent so far is acknowledged by the server."""
        self.device.flush(timeout)

    def close(self, timeout: float | None = None) -> None:
        self.device.close(timeout)

    def __enter__(self) -> Connect:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    async def _on_command(self, name: str, args: JsonObject) -> None:
        value = dumps({"name": name, "args": args}) if args else name
        with self._cond:
            self._offset += 1
            self._inbox.append(
                Message(
                    topic=self.topic,
                    partition=self.receiving_partition,
                    offset=self._offset,
                    timestamp=time.time_ns() // 1_000_000,
                    key=self.device_id.encode() if self.device_id else None,
                    value=value.encode(),
                    name=name,
                    args=dict(args),
                )
            )
            self._cond.notify_all()

    def _check_id(self) -> None:
        if self._checked_id:
            return
        name = self.device.device_name
        if name is not None:
            self._checked_id = True
            if name != self.device_id:
                log.warning(
                    "device_id %r, but the token belongs to device %r", self.device_id, name
                )
