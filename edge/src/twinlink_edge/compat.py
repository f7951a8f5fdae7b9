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
samples go to the stream `stream` (default `telemetry`).

As with the thesis's Kafka client, `Connect()` returns connected, with the commands queued for
the device while it was away already received, so the listing's single `receive()` finds
them. A command counts as delivered only when `receive()` hands it over; one never handed over
is answered failed ("not read by the device") when the script closes or exits."""

from __future__ import annotations

import logging
import os
import time
from dataclasses import dataclass, field
from typing import Any

from ._inbox import HeldCommand, Inbox
from ._protocol import JsonObject, dumps
from .sync import Device

__all__ = ["Connect", "Message"]

log = logging.getLogger("twinlink_edge")

IDLE_WAIT = 0.05  # seconds an idle receive() waits, so a polling loop does not spin
CONNECT_TIMEOUT = 10.0  # seconds Connect() waits for the connection, unless told otherwise


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
    """The thesis's `Connect`: connects (and returns once connected), `add_to_message` sets
    values in the pending message, `send` sends it as one sample stamped with the device clock
    (the values stay for the next message; later calls update them), `receive` hands over the
    commands that arrived since the last call as `{topic: [Message, ...]}` (each is answered
    `delivered`, then `succeeded`, as it is handed over).

    `ConnectionError` when no connection is made within `connect_timeout` seconds (default
    10), with the reason (an unknown token, a server that does not answer)."""

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
        connect_timeout: float = CONNECT_TIMEOUT,
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
        self._offset = 0
        self._idle = False  # the last receive() returned nothing
        self._sent = False  # send() was called since the last receive()
        self.device = Device(
            url,
            token,
            stream=stream,
            flush_interval=flush_interval,
            connect_timeout=connect_timeout,
            **options,
        )
        # Commands without a handler of their own wait until receive() takes them.
        self._inbox = self.device.aio._dispatcher.inbox = Inbox()
        self.device.start()
        try:
            self._connect(connect_timeout)
        except BaseException:
            self.device.close(0)
            raise
        self._check_id()

    def _connect(self, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        if self.device.wait_connected(timeout):
            # The queued commands follow the welcome: after a round trip they are here.
            try:
                left = max(0.0, deadline - time.monotonic())
                self.device._call(self.device.aio._round_trip(left))
                return
            except TimeoutError:
                pass
        reason = self.device.last_error or f"{self.device.aio.url} did not answer"
        raise ConnectionError(f"not connected within {timeout:g} s: {reason}")

    def add_to_message(self, name: str, value: Any) -> None:
        """Set `name` in the pending message (a new attribute, or an update of one)."""
        self.message[name] = value

    def send(self) -> None:
        """Send the pending message as one sample, stamped now."""
        if not self.message:
            log.warning("send(): the message is empty; add_to_message() first")
            return
        self.device.add(dict(self.message), time.time_ns())
        self._sent = True

    def receive(self, timeout_ms: int | None = None) -> dict[str, list[Message]]:
        """The commands received since the last call, as `{topic: [Message, ...]}`, or `{}`.
        Each counts as delivered (and succeeded) once handed over here.

        Returns at once, except when the previous call also returned nothing and nothing was
        sent in between (a loop waiting for a command): then it waits up to 50 ms for one, so
        such a loop does not spin. `timeout_ms` sets the wait instead."""
        if timeout_ms is not None:
            wait = max(0.0, timeout_ms / 1000)
        else:
            wait = IDLE_WAIT if self._idle and not self._sent else 0.0
        # Taking happens on the device's loop; an empty inbox needs no trip there (len() is
        # safe from this thread: a command that lands just after is taken by the next call).
        taken = self.device._call(self._take(wait)) if wait or len(self._inbox) else []
        messages = [self._message(command) for command in taken]
        self._idle = not messages
        self._sent = False
        return {self.topic: messages} if messages else {}

    async def _take(self, wait: float) -> list[HeldCommand]:
        await self._inbox.wait(wait)
        return self.device.aio._dispatcher.take()

    def _message(self, command: HeldCommand) -> Message:
        name, args = command.name, command.args
        value = dumps({"name": name, "args": args}) if args else name
        self._offset += 1
        return Message(
            topic=self.topic,
            partition=self.receiving_partition,
            offset=self._offset,
            timestamp=command.arrived_ns // 1_000_000,
            key=self.device_id.encode() if self.device_id else None,
            value=value.encode(),
            name=name,
            args=dict(args),
        )

    def flush(self, timeout: float | None = None) -> None:
        """Wait until every message sent so far is acknowledged by the server."""
        self.device.flush(timeout)

    def close(self, timeout: float | None = None) -> None:
        """Answer the commands never handed over `failed` ("not read by the device"), wait
        up to `timeout` seconds (default 10) for the server to have them and every message
        sent, and disconnect. A script that never calls it is closed at exit."""
        self.device.close(timeout)

    def __enter__(self) -> Connect:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _check_id(self) -> None:
        name = self.device.device_name
        if self.device_id is not None and name != self.device_id:
            log.warning("device_id %r, but the token belongs to device %r", self.device_id, name)
