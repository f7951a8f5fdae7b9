"""One device's MQTT side of its session, in either mode.

From the device: a PUBLISH on one of its topics becomes a protocol message for its
`DeviceLink` (docs/protocol.md), remembering what must be acknowledged once the platform has
handled it (a `Receipt`: the packet id and QoS). From the platform: what `DeviceSession`
sends (`Transport.send_text`) becomes PUBACKs (an `ack` means the batch is durable) and
publishes to the device's topics. Where those go is the `Outlet`: the device's own connection
(embedded) or the external broker.
"""

from __future__ import annotations

import asyncio
import itertools
import logging
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Protocol

import orjson

from twinlink.domain.samples import BatchError
from twinlink.ingest.link import DeviceLink, ServerSeq
from twinlink.ingest.mqtt.packets import PAYLOAD_FORMAT_INVALID, SUCCESS
from twinlink.ingest.mqtt.payloads import (
    dumps,
    read_telemetry,
    reported_message,
    result_message,
)
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import (
    DELIVERED,
    REPORTED,
    RESULT,
    STATUS,
    TELEMETRY,
    DeviceTopics,
    Route,
)

log = logging.getLogger("twinlink.mqtt")

MAX_HELD_COMMANDS = 100
MAX_MERGED_SAMPLES = 10_000


@dataclass(frozen=True, slots=True)
class Receipt:
    """A QoS 1 or 2 PUBLISH waiting for its PUBACK (PUBREC); `origin` is the connection it
    came on (external mode: a packet id means nothing on the next connection)."""

    packet_id: int
    qos: int
    origin: object = None


class Outlet(Protocol):
    """Where a device's MQTT traffic goes: its connection, or the external broker."""

    def deliverable(self, topic: str) -> bool:
        """Whether a publish to `topic` reaches the device now (it has subscribed)."""
        ...

    def publish(self, topic: str, payload: bytes, qos: int, retain: bool = False) -> None: ...

    def acknowledge(self, receipts: Iterable[Receipt], reason: int) -> None: ...

    async def drain(self) -> None: ...

    def fail(self, text: str) -> None:
        """A message could not be stored (a transient failure): end the connection without
        acknowledging, so MQTT delivers the unacknowledged messages again."""
        ...

    def session_closed(self, code: int, reason: str) -> None:
        """The platform closed the device's session (token revoked, device deleted, a newer
        connection of the device took over)."""
        ...


class DeviceBridge:
    """The `Transport` of the device's session, and the way its publishes reach the link."""

    def __init__(
        self, outlet: Outlet, topics: DeviceTopics, status: MqttStatus, retain_desired: bool
    ) -> None:
        self.outlet = outlet
        self.topics = topics
        self.status = status
        self.retain_desired = retain_desired
        self.link: DeviceLink | None = None
        self.seq = ServerSeq()
        self._by_seq: dict[int, list[Receipt]] = {}
        self._by_ref: dict[int, list[Receipt]] = {}
        self._refs = itertools.count(1)
        self._held_commands: list[tuple[str, bytes]] = []
        self._held_desired: bytes | None = None
        # Messages without `seq` that arrived together, one batch per stream (see `merge`).
        self._merging: dict[str | None, tuple[list[Any], list[Receipt]]] = {}
        self._clock = ServerSeq()  # receipt times: increasing, so no two samples share one
        self._answered = asyncio.Event()

    # -- from the device -------------------------------------------------------------------

    async def receive(self, route: Route, payload: bytes, receipt: Receipt | None) -> None:
        """Hand one publish to the platform; its receipt is acknowledged once handled."""
        link = self.link
        assert link is not None, "receive before the session is open"
        self.status.received[route.kind] += 1
        try:
            if route.kind == TELEMETRY:
                batch = read_telemetry(payload, route.detail)
                if batch.seq is None and batch.time_unit in (None, "ns"):
                    await self._merge(batch.samples, batch.stream, receipt)
                    return
                seq = self.seq.next() if batch.seq is None else batch.seq
                self._expect(self._by_seq, seq, receipt)
                await link.dispatch(batch.message(seq))
            elif route.kind in (RESULT, DELIVERED):
                assert route.detail is not None
                message = (
                    result_message(route.detail, payload)
                    if route.kind == RESULT
                    else {"type": DELIVERED, "id": route.detail}
                )
                await link.dispatch(message)
                self._acknowledge([receipt], SUCCESS)
            elif route.kind == REPORTED:
                ref = next(self._refs)
                message = reported_message(payload, ref)
                self._expect(self._by_ref, ref, receipt)
                await link.dispatch(message)
            else:
                assert route.kind == STATUS  # presence: the connection (or the external
                self._acknowledge([receipt], SUCCESS)  # service) acts on it
        except BatchError as err:
            self.refuse(receipt, "malformed", str(err), PAYLOAD_FORMAT_INVALID)

    async def _merge(self, samples: list[Any], stream: str | None, receipt: Receipt | None) -> None:
        """Samples of a message without `seq` join the batch being gathered for their stream:
        a burst of one-sample messages is stored as one batch (one commit, one ack that
        releases all their PUBACKs), not one batch each. A sample without `time` gets the
        time it arrived now, as it would have alone."""
        now = self._clock.next()
        for sample in samples:
            if isinstance(sample, dict) and "time" not in sample:
                sample["time"] = now
        pending = self._merging.get(stream)
        if pending is not None and len(pending[0]) + len(samples) > MAX_MERGED_SAMPLES:
            await self.flush()  # a large message goes alone, within a batch's limit
        gathered, receipts = self._merging.setdefault(stream, ([], []))
        gathered.extend(samples)
        if receipt is not None:
            receipts.append(receipt)
        if len(gathered) >= MAX_MERGED_SAMPLES:
            await self.flush()

    async def flush(self) -> None:
        """Hand the gathered batches to the platform (after each read from the socket)."""
        if not self._merging or self.link is None:
            return
        merging, self._merging = self._merging, {}
        for stream, (samples, receipts) in merging.items():
            seq = self.seq.next()
            if receipts:
                self._by_seq[seq] = receipts
            message: dict[str, Any] = {"type": "samples", "seq": seq, "samples": samples}
            if stream is not None:
                message["stream"] = stream
            await self.link.dispatch(message)

    def refuse(self, receipt: Receipt | None, kind: str, text: str, reason: int) -> None:
        """A publish the platform will never take: counted, told on `errors`, and
        acknowledged (with `reason` in MQTT 5) so the client does not send it again."""
        self.status.error(kind, text)
        self._publish_error({"type": "error", "message": text, "fatal": False})
        self._acknowledge([receipt], reason)

    @staticmethod
    def _expect(pending: dict[int, list[Receipt]], key: int, receipt: Receipt | None) -> None:
        if receipt is not None:
            pending.setdefault(key, []).append(receipt)

    def _acknowledge(self, receipts: list[Receipt | None], reason: int) -> None:
        due = [r for r in receipts if r is not None]
        if due:
            self.outlet.acknowledge(due, reason)

    # -- from the platform (Transport) ---------------------------------------------------------

    async def send_text(self, data: str) -> None:
        message = orjson.loads(data)
        kind = message.get("type")
        if kind == "ack":
            self._on_ack(message)
        elif kind == "error":
            self._on_error(message)
        elif kind == "reported_ack":
            receipts = self._by_ref.pop(message.pop("id", None), [])
            self.outlet.acknowledge(receipts, SUCCESS)
            self._publish_if_subscribed(self.topics.acks, message)
        elif kind == "command":
            self._publish_command(message)
        elif kind in ("desired", "welcome"):
            self._publish_desired(message)
        self._answered.set()
        await self.outlet.drain()  # pong: MQTT has its own keep-alive

    async def settle(self, timeout: float) -> None:
        """Wait (at most `timeout` s) until what was handed on is answered, so a shutdown
        sends the PUBACKs of stored messages before it closes the connection."""
        try:
            async with asyncio.timeout(timeout):
                while self._by_seq or self._by_ref:
                    self._answered.clear()
                    await self._answered.wait()
        except TimeoutError:
            return

    async def close(self, code: int, reason: str) -> None:
        self.outlet.session_closed(code, reason)

    def _on_ack(self, message: dict[str, Any]) -> None:
        self.outlet.acknowledge(self._by_seq.pop(message["seq"], []), SUCCESS)
        self.status.samples += int(message.get("accepted", 0))
        self._publish_if_subscribed(self.topics.acks, message)
        count = int(message.get("rejected_count", 0))
        if count:
            first = message["rejected"][0]
            text = f"{count} sample(s) rejected; #{first['index']}: {first['reason']}"
            self.status.error("rejected_samples", text)
            self._publish_error(
                {"type": "error", "message": text, "fatal": False, "seq": message["seq"]}
            )

    def _on_error(self, message: dict[str, Any]) -> None:
        text = str(message.get("message"))
        seq, op = message.get("seq"), message.get("op")
        receipts: list[Receipt] | None = None
        if isinstance(seq, int) and seq in self._by_seq:
            receipts = self._by_seq.pop(seq)
        elif op == "reported":
            receipts = self._by_ref.pop(message.pop("id", None), [])
        kind = "refused_batch" if seq is not None else f"refused_{op}" if op else "device_error"
        self.status.error(kind, text)
        self._publish_error(message)
        if not receipts:
            return
        if message.get("retry"):
            self.outlet.fail(text)
        else:
            self.outlet.acknowledge(receipts, PAYLOAD_FORMAT_INVALID)

    # -- publishing to the device ----------------------------------------------------------

    def _publish_error(self, message: dict[str, Any]) -> None:
        self._publish_if_subscribed(self.topics.errors, message)

    def _publish_if_subscribed(self, topic: str, message: dict[str, Any]) -> None:
        # Acks and errors answer what the device just sent: not held for a later subscriber.
        if self.outlet.deliverable(topic):
            self._send(topic, dumps(message), 0)

    def _publish_command(self, message: dict[str, Any]) -> None:
        topic = self.topics.command(str(message["id"]))
        body = {k: v for k, v in message.items() if k != "type"}
        if self.outlet.deliverable(topic):
            self._send(topic, dumps(body), 1)
            return
        # Held until the device subscribes: a command sent in the moment between CONNECT and
        # SUBSCRIBE (queued commands are sent right at connect) is not lost.
        self._held_commands.append((topic, dumps(body)))
        if len(self._held_commands) > MAX_HELD_COMMANDS:
            del self._held_commands[0]
            self.status.error("held_dropped", "a command held for a device that never subscribed")

    def _publish_desired(self, message: dict[str, Any]) -> None:
        if message["type"] == "welcome":
            body = {"properties": message.get("desired", {}),
                    "version": message.get("desired_version", 0)}  # fmt: skip
        else:
            body = {"properties": message["properties"], "version": message["version"]}
        payload = dumps(body)
        if self.outlet.deliverable(self.topics.desired):
            self._send(self.topics.desired, payload, 1, retain=self.retain_desired)
        else:
            self._held_desired = payload  # only the newest delta matters

    def subscribed(self) -> None:
        """The device subscribed: send what was held for topics it now reaches."""
        if self._held_desired is not None and self.outlet.deliverable(self.topics.desired):
            payload, self._held_desired = self._held_desired, None
            self._send(self.topics.desired, payload, 1, retain=self.retain_desired)
        keep = []
        for topic, payload in self._held_commands:
            if self.outlet.deliverable(topic):
                self._send(topic, payload, 1)
            else:
                keep.append((topic, payload))
        self._held_commands = keep

    def _send(self, topic: str, payload: bytes, qos: int, retain: bool = False) -> None:
        self.status.sent += 1
        self.outlet.publish(topic, payload, qos, retain)
