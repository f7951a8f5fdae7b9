"""One device's connection to the embedded listener: CONNECT with its token, then packets.

The connection is the device's `Outlet`: acknowledgements and publishes from the platform
are written to its socket, publishes only to topics it subscribed to.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import secrets
import time
from collections.abc import Iterable
from typing import Any, Protocol

from twinlink.auth.service import AuthError
from twinlink.domain.errors import StorageError
from twinlink.domain.records import Device
from twinlink.ingest.link import connect_device, disconnect_device
from twinlink.ingest.mqtt import packets as mq
from twinlink.ingest.mqtt._wire import (
    ASSIGNED_CLIENT_ID,
    AUTH_METHOD,
    MAXIMUM_PACKET_SIZE,
    REASON_STRING,
    SHARED_AVAILABLE,
    SUBSCRIPTION_ID_AVAILABLE,
    TOPIC_ALIAS,
    MalformedPacket,
)
from twinlink.ingest.mqtt.bridge import DeviceBridge, Receipt
from twinlink.ingest.mqtt.platform import Platform
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import (
    DeviceTopics,
    Route,
    TopicError,
    TopicScheme,
    matches,
    valid_filter,
)

log = logging.getLogger("twinlink.mqtt")

CONNECT_TIMEOUT_S = 10.0
READ_BYTES = 256 * 1024
SETTLE_S = 5.0  # at shutdown, how long to wait for the acks of what was handed on
MAX_ROUTES = 64  # topics remembered per connection
_CLOSE_REASONS = {4409: mq.SESSION_TAKEN_OVER, 4401: mq.NOT_AUTHORIZED}


class Listener(Protocol):
    """What a connection uses of the listener that accepted it (listener.py): a protocol, so
    this module does not import the one that imports it."""

    platform: Platform
    scheme: TopicScheme
    status: MqttStatus
    max_packet_bytes: int

    def register(self, connection: DeviceConnection) -> None: ...

    def unregister(self, connection: DeviceConnection) -> None: ...


class DeviceConnection:
    def __init__(
        self, listener: Listener, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
    ) -> None:
        self.listener = listener
        self.status = listener.status
        self.reader = reader
        self.writer = writer
        self.packets = mq.PacketReader(listener.max_packet_bytes)
        self.version = mq.V311
        self.client_id = ""
        self.keep_alive = 0
        self.last_seen = time.monotonic()
        self.device: Device | None = None
        self.bridge: DeviceBridge | None = None
        self.subscriptions: dict[str, tuple[list[str], int]] = {}  # filter -> (levels, QoS)
        self.awaiting_release: set[int] = set()  # QoS 2: PUBREC sent, PUBREL not yet in
        self._routes: dict[str, Route] = {}
        self._early: list[mq.Packet] = []
        self._packet_id = 0
        self._recheck: asyncio.Task[None] | None = None
        self.shutting_down = False

    # -- life -------------------------------------------------------------------------------

    async def serve(self) -> None:
        try:
            connect = await self._read_connect()
            if connect is not None and await self._accept(connect):
                await self._read_loop()
        except mq.ProtocolViolation as err:
            if err.reason == mq.UNSUPPORTED_VERSION:  # a CONNACK of 3.1.1, which all can read
                self._refuse(err.reason, str(err))
            else:
                self.drop(err.reason, "protocol_error", str(err))
        except MalformedPacket as err:
            self.drop(mq.MALFORMED, "malformed_packet", str(err))
        except (ConnectionError, TimeoutError):
            pass
        finally:
            await self._finish()

    async def _read_connect(self) -> mq.Connect | None:
        async with asyncio.timeout(CONNECT_TIMEOUT_S):
            received: list[mq.Packet] = []
            while not received:
                data = await self.reader.read(READ_BYTES)
                if not data:
                    return None
                received = self.packets.feed(data)
        first, *self._early = received
        if not isinstance(first, mq.Connect):
            raise mq.ProtocolViolation("the first packet must be CONNECT")
        return first

    async def _accept(self, connect: mq.Connect) -> bool:
        self.version = connect.version
        token = connect.password.decode(errors="replace") if connect.password else None
        token = token or connect.username
        if AUTH_METHOD in connect.properties:
            return self._refuse(mq.BAD_AUTH_METHOD, "enhanced authentication is not supported")
        if not token:
            return self._refuse(mq.NOT_AUTHORIZED, "a device token is required as the password")
        try:
            device = await self.listener.platform.devices.authenticate(token)
        except AuthError as err:
            return self._refuse(mq.BAD_CREDENTIALS, str(err))
        except StorageError as err:  # the token could not be read: not a bad one; retry
            return self._refuse(mq.SERVER_UNAVAILABLE, str(err))
        if not connect.client_id and not connect.clean_start and self.version != mq.V5:
            return self._refuse(mq.CLIENT_ID_INVALID, "an empty client id needs a clean session")
        props = self._connack_properties(connect, device)
        self.writer.write(mq.encode_connack(self.version, mq.SUCCESS, False, props))
        self.device, self.keep_alive = device, connect.keep_alive
        self.listener.register(self)
        self.bridge = DeviceBridge(self, self._topics(device), self.status, retain_desired=False)
        platform = self.listener.platform
        self.bridge.link = await connect_device(platform.hub, platform.ingest, device, self.bridge)
        self._recheck = asyncio.create_task(self._recheck_token(token))
        self.status.connects += 1
        return True

    def _topics(self, device: Device) -> DeviceTopics:
        return DeviceTopics(self.listener.scheme, device.twin_slug, device.name)

    def _connack_properties(self, connect: mq.Connect, device: Device) -> dict[int, Any]:
        self.client_id = connect.client_id or f"{device.name}-{secrets.token_hex(6)}"
        if self.version != mq.V5:
            return {}
        props: dict[int, Any] = {
            MAXIMUM_PACKET_SIZE: self.listener.max_packet_bytes,
            SHARED_AVAILABLE: 0,
            SUBSCRIPTION_ID_AVAILABLE: 0,
        }
        if not connect.client_id:
            props[ASSIGNED_CLIENT_ID] = self.client_id
        return props

    def _refuse(self, reason: int, text: str) -> bool:
        self.status.refused[_REFUSALS.get(reason, "other")] += 1
        props = {REASON_STRING: text} if self.version == mq.V5 else None
        self.writer.write(mq.encode_connack(self.version, reason, False, props))
        log.info("mqtt connection refused", extra={"event": "mqtt_refused", "reason": text})
        return False

    async def _recheck_token(self, token: str) -> None:
        """A token revoked (or a device deleted) while connected ends the connection."""
        assert self.bridge is not None and self.bridge.link is not None
        session = self.bridge.link.session
        devices = self.listener.platform.devices
        while not session.closed.is_set():
            await asyncio.sleep(devices.recheck_delay())
            try:
                await devices.authenticate(token)
            except AuthError as err:
                await session.close(4401, str(err))
            except Exception as err:  # not left open unchecked (as on the device WebSocket)
                log.warning("device token check failed; closing: %s", err,
                            extra={"event": "device_recheck_failed"})  # fmt: skip
                await session.close(1011, "the device token could not be checked again")

    def shut_down(self) -> None:
        """The listener closes: read nothing more (the read loop sees the end), then finish."""
        self.shutting_down = True
        transport = self.writer.transport
        if isinstance(transport, asyncio.ReadTransport):  # no data after the end (asyncio)
            transport.pause_reading()
        self.reader.feed_eof()

    async def _finish(self) -> None:
        self.listener.unregister(self)
        try:
            if self._recheck is not None:
                self._recheck.cancel()
                await asyncio.gather(self._recheck, return_exceptions=True)
            if self.bridge is not None and self.bridge.link is not None:
                await self.bridge.flush()  # what came with the DISCONNECT (or before an error)
                if self.shutting_down:  # the client is still there: send it the PUBACKs due
                    await self.bridge.settle(SETTLE_S)
                    self.drop(mq.SERVER_SHUTTING_DOWN, "", "")
                await disconnect_device(self.bridge.link)
        finally:
            self.writer.close()
            with contextlib.suppress(ConnectionError, OSError):
                await self.writer.wait_closed()

    def drop(self, reason: int, kind: str, text: str) -> None:
        """End the connection (MQTT 5: with a DISCONNECT saying why)."""
        if kind:
            self.status.error(kind, text)
        if self.version == mq.V5 and not self.writer.is_closing():
            self.writer.write(mq.encode_disconnect(self.version, reason))
        self.writer.close()

    # -- packets ----------------------------------------------------------------------------

    async def _read_loop(self) -> None:
        received, self._early = self._early, []
        while True:
            for packet in received:
                if not await self._handle(packet):
                    return
            if self.bridge is not None:
                await self.bridge.flush()
            data = await self.reader.read(READ_BYTES)
            if not data:
                return
            self.last_seen = time.monotonic()
            received = self.packets.feed(data)

    async def _handle(self, packet: mq.Packet) -> bool:
        """Act on one packet; False when the client disconnected."""
        if isinstance(packet, mq.Publish):
            await self._on_publish(packet)
        elif isinstance(packet, mq.Ack):
            if packet.kind == mq.PUBREL:
                self.awaiting_release.discard(packet.packet_id)
                self.writer.write(mq.encode_ack(mq.PUBCOMP, packet.packet_id, self.version))
        elif isinstance(packet, mq.Subscribe):
            self._on_subscribe(packet)
        elif isinstance(packet, mq.Unsubscribe):
            for topic_filter in packet.filters:
                self.subscriptions.pop(topic_filter, None)
            count = len(packet.filters)
            self.writer.write(mq.encode_unsuback(self.version, packet.packet_id, count))
        elif isinstance(packet, mq.Simple) and packet.kind == mq.PINGREQ:
            self.writer.write(mq.PINGRESP_BYTES)
        elif isinstance(packet, mq.Simple) and packet.kind == mq.DISCONNECT:
            return False
        else:
            raise mq.ProtocolViolation(f"unexpected {type(packet).__name__} packet")
        return True

    async def _on_publish(self, packet: mq.Publish) -> None:
        assert self.bridge is not None and self.device is not None
        receipt = Receipt(packet.packet_id, packet.qos) if packet.qos else None
        if packet.qos == 2 and packet.packet_id in self.awaiting_release:
            self.writer.write(mq.encode_ack(mq.PUBREC, packet.packet_id, self.version))
            return  # a resend of a QoS 2 message already taken
        if packet.properties and TOPIC_ALIAS in packet.properties:
            raise mq.ProtocolViolation("topic aliases are not enabled", mq.TOPIC_ALIAS_INVALID)
        route = self._routes.get(packet.topic)
        if route is None:
            try:
                route = self.listener.scheme.route(packet.topic)
            except TopicError as err:
                self.bridge.refuse(receipt, "unknown_topic", str(err), mq.TOPIC_NAME_INVALID)
                return
            if (route.twin, route.device) != (self.device.twin_slug, self.device.name):
                text = f"{packet.topic!r} is not a topic of device {self.device.name!r}"
                self.bridge.refuse(receipt, "not_authorized", text, mq.NOT_AUTHORIZED)
                return
            if len(self._routes) < MAX_ROUTES:
                self._routes[packet.topic] = route
        await self.bridge.receive(route, packet.payload, receipt)

    def _on_subscribe(self, packet: mq.Subscribe) -> None:
        assert self.bridge is not None
        codes = []
        for topic_filter, options in packet.filters:
            if not valid_filter(topic_filter) or topic_filter.startswith("$"):
                codes.append(mq.TOPIC_FILTER_INVALID if self.version == mq.V5 else 0x80)
                self.status.error("subscribe_refused", f"{topic_filter!r} is not a topic filter")
            elif not self.bridge.topics.reachable(topic_filter):
                codes.append(mq.NOT_AUTHORIZED if self.version == mq.V5 else 0x80)
                text = f"{topic_filter!r} matches none of the topics of this device"
                self.status.error("subscribe_refused", text)
            else:
                qos = min(options & 3, 1)  # the platform publishes with QoS 0 or 1
                self.subscriptions[topic_filter] = (topic_filter.split("/"), qos)
                codes.append(qos)
        self.writer.write(mq.encode_suback(self.version, packet.packet_id, codes))
        self.bridge.subscribed()

    # -- the Outlet -------------------------------------------------------------------------

    def _granted(self, topic: str) -> int:
        """The highest QoS of the subscriptions matching `topic`; -1 when none does."""
        levels = topic.split("/")
        return max((q for f, q in self.subscriptions.values() if matches(f, levels)), default=-1)

    def deliverable(self, topic: str) -> bool:
        return self._granted(topic) >= 0

    def publish(self, topic: str, payload: bytes, qos: int, retain: bool = False) -> None:
        qos = min(qos, self._granted(topic))
        if qos < 0 or self.writer.is_closing():
            return
        packet_id = 0
        if qos:
            self._packet_id = self._packet_id % 65535 + 1
            packet_id = self._packet_id
        self.writer.write(mq.encode_publish(self.version, topic, payload, qos, packet_id))

    def acknowledge(self, receipts: Iterable[Receipt], reason: int) -> None:
        out = []
        for receipt in receipts:
            if receipt.qos == 2:
                self.awaiting_release.add(receipt.packet_id)
            kind = mq.PUBACK if receipt.qos == 1 else mq.PUBREC
            out.append(mq.encode_ack(kind, receipt.packet_id, self.version, reason))
        if out and not self.writer.is_closing():
            self.writer.write(b"".join(out))

    async def drain(self) -> None:
        await self.writer.drain()

    def fail(self, text: str) -> None:
        self.drop(mq.UNSPECIFIED_ERROR, "store_failed", text)

    def session_closed(self, code: int, reason: str) -> None:
        if code != 1000:  # 1000: the connection ended first and closed the session itself
            self.drop(_CLOSE_REASONS.get(code, mq.SERVER_SHUTTING_DOWN), "", reason)

    def take_over(self) -> None:
        """A newer connection with the same client id came (MQTT 3.1.4-3)."""
        self.drop(mq.SESSION_TAKEN_OVER, "", "")


_REFUSALS = {
    mq.UNSUPPORTED_VERSION: "protocol_version",
    mq.BAD_AUTH_METHOD: "bad_auth_method",
    mq.NOT_AUTHORIZED: "no_token",
    mq.BAD_CREDENTIALS: "bad_token",
    mq.CLIENT_ID_INVALID: "client_id",
}
