"""External mode: devices talk to a broker the user runs (Mosquitto, EMQX, HiveMQ), which
authenticates them; the platform is one more client of it, with its own credentials.

It subscribes to every device's topics (`TopicScheme.subscriptions`), finds the device a
topic names (twin slug + device name) and opens a session for each device it hears from, so
commands route to it and it shows connected; a device's `status` message `offline` (its will
message) ends the session. A QoS 1 message is acknowledged to the broker only once the
platform has handled it (telemetry: once durable). The platform's session at the broker
lasts (clean session 0), so messages sent while it is away wait there.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Iterable

from twinlink.domain.records import Device
from twinlink.ingest.link import connect_device, disconnect_device
from twinlink.ingest.mqtt import packets as mq
from twinlink.ingest.mqtt._wire import MalformedPacket
from twinlink.ingest.mqtt.bridge import DeviceBridge, Receipt
from twinlink.ingest.mqtt.client import BrokerAddress, BrokerConnection, BrokerRefused
from twinlink.ingest.mqtt.platform import Platform
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import STATUS, DeviceTopics, Route, TopicError, TopicScheme

log = logging.getLogger("twinlink.mqtt")

KEEP_ALIVE_S = 30
RETRY_MIN_S, RETRY_MAX_S = 0.5, 30.0
SETTLE_S = 5.0
Key = tuple[str, str]  # (twin slug, device name)


class ExternalBroker:
    def __init__(
        self,
        platform: Platform,
        url: str,
        username: str | None,
        password: str | None,
        client_id: str,
        scheme: TopicScheme,
        status: MqttStatus,
    ) -> None:
        self.platform = platform
        self.address = BrokerAddress.parse(url)
        self.credentials = (username, password)
        self.client_id = client_id
        self.scheme = scheme
        self.status = status
        self.connection: BrokerConnection | None = None
        self.bridges: dict[Key, DeviceBridge] = {}
        self._device_ids: dict[Key, int] = {}
        self._known: dict[Key, Device | None] = {}
        self._known_generation = -1
        self._dirty: set[DeviceBridge] = set()
        self._task: asyncio.Task[None] | None = None

    # -- life -------------------------------------------------------------------------------

    async def open(self) -> None:
        """Connect; BrokerRefused when the broker refuses the credentials or subscriptions. A
        broker that cannot be reached is retried in the background."""
        self.status.address = str(self.address)
        self.status.set_state("connecting")
        try:
            await self._connect()
        except (OSError, TimeoutError, ConnectionError, MalformedPacket) as err:
            self.status.error("broker_unreachable", f"{self.address}: {err}")
            self.status.set_state("reconnecting")
        self._task = asyncio.create_task(self._run(), name="mqtt-external")

    async def close(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
        await self._end_sessions(settle=True)
        if self.connection is not None:
            await self.connection.close()
            self.connection = None
        self.status.set_state("stopped")

    async def _connect(self) -> None:
        connection = await BrokerConnection.open(
            self.address, self.client_id, *self.credentials, KEEP_ALIVE_S
        )
        try:
            await connection.subscribe(self.scheme.subscriptions())
        except BaseException:
            await connection.close()
            raise
        self.connection = connection
        self.status.connects += 1
        self.status.set_state("connected")
        log.info("mqtt broker connected", extra={"event": "mqtt_broker_connected",
                                                 "broker": str(self.address)})  # fmt: skip

    async def _run(self) -> None:
        delay = RETRY_MIN_S
        while True:
            if self.connection is None:
                try:
                    await self._connect()
                    delay = RETRY_MIN_S
                except (OSError, TimeoutError, ConnectionError, MalformedPacket) as err:
                    self.status.error("broker_unreachable", f"{self.address}: {err}")
                except BrokerRefused as err:  # the user may fix the broker's side meanwhile
                    self.status.error("broker_refused", str(err))
                    delay = RETRY_MAX_S
                if self.connection is None:
                    await asyncio.sleep(delay)
                    delay = min(delay * 2, RETRY_MAX_S)
                    continue
            assert self.connection is not None
            try:
                await self._serve(self.connection)
            except (OSError, ConnectionError, MalformedPacket) as err:
                self.status.error("broker_lost", f"{self.address}: {err}")
            await self._lost()

    async def _lost(self) -> None:
        """The connection ended: devices are offline until they are heard from again."""
        if self.connection is not None:
            await self.connection.close()
            self.connection = None
        self.status.set_state("reconnecting")
        await self._end_sessions(settle=False)

    async def _end_sessions(self, settle: bool) -> None:
        bridges, self.bridges = list(self.bridges.values()), {}
        self._device_ids.clear()
        for bridge in bridges:
            await self._close_bridge(bridge, settle)
        self.status.clients = 0

    async def _close_bridge(self, bridge: DeviceBridge, settle: bool) -> None:
        if bridge.link is None:
            return
        await bridge.flush()
        if settle:
            await bridge.settle(SETTLE_S)
        await disconnect_device(bridge.link)

    # -- messages ---------------------------------------------------------------------------

    async def _serve(self, connection: BrokerConnection) -> None:
        pinger = asyncio.create_task(self._ping(connection))
        try:
            while not connection.closed:
                for packet in await connection.read():
                    if isinstance(packet, mq.Publish):
                        await self._on_publish(connection, packet)
                dirty, self._dirty = self._dirty, set()
                for bridge in dirty:
                    await bridge.flush()
        finally:
            pinger.cancel()

    async def _ping(self, connection: BrokerConnection) -> None:
        while not connection.closed:
            await asyncio.sleep(KEEP_ALIVE_S / 2)
            connection.ping()

    async def _on_publish(self, connection: BrokerConnection, packet: mq.Publish) -> None:
        receipt = Receipt(packet.packet_id, packet.qos, connection) if packet.qos else None
        try:
            route = self.scheme.route(packet.topic)
        except TopicError as err:
            self._skip(receipt, "unknown_topic", str(err))
            return
        key = (route.twin, route.device)
        if route.kind == STATUS and packet.payload.strip().lower() == b"offline":
            bridge = self.bridges.pop(key, None)  # the device's will: it is gone
            if bridge is not None:
                self._device_ids.pop(key, None)
                self.status.clients = len(self.bridges)
                await self._close_bridge(bridge, settle=False)
            self._skip(receipt, "", "")
            return
        bridge = await self._bridge(route)
        if bridge is None:
            text = f"{packet.topic!r}: twin {route.twin!r} has no device {route.device!r}"
            self._skip(receipt, "unknown_device", text)
            return
        await bridge.receive(route, packet.payload, receipt)
        self._dirty.add(bridge)

    def _skip(self, receipt: Receipt | None, kind: str, text: str) -> None:
        if kind:
            self.status.error(kind, text)
        if receipt is not None:
            ExternalOutlet.ack(self, [receipt])

    async def _bridge(self, route: Route) -> DeviceBridge | None:
        """The session of the device a topic names, opened on first need; None when the
        device does not exist (any more)."""
        key = (route.twin, route.device)
        device = await self._device(key)
        bridge = self.bridges.get(key)
        if bridge is not None and (device is None or self._device_ids.get(key) != device.id):
            del self.bridges[key]  # deleted, or deleted and made again
            await self._close_bridge(bridge, settle=False)
            bridge = None
        if device is None:
            return None
        if bridge is None or bridge.link is None or bridge.link.session.closed.is_set():
            topics = DeviceTopics(self.scheme, route.twin, route.device)
            bridge = DeviceBridge(ExternalOutlet(self, key), topics, self.status, True)
            self.bridges[key], self._device_ids[key] = bridge, device.id
            hub, ingest = self.platform.hub, self.platform.ingest
            bridge.link = await connect_device(hub, ingest, device, bridge)
            self.status.clients = len(self.bridges)
        return bridge

    async def _device(self, key: Key) -> Device | None:
        registry = self.platform.devices.registry
        if registry.generation != self._known_generation:
            self._known.clear()  # a device or twin was added or removed
            self._known_generation = registry.generation
        if key not in self._known:
            store = self.platform.devices.store
            twin = await store.get_twin(key[0])
            self._known[key] = None if twin is None else await store.get_device(twin.id, key[1])
        return self._known[key]


class ExternalOutlet:
    """A device's traffic through the broker: publishes go to its topics there, acks to the
    broker for the messages it delivered to the platform."""

    def __init__(self, broker: ExternalBroker, key: Key) -> None:
        self.broker = broker
        self.key = key

    def deliverable(self, topic: str) -> bool:
        # The broker delivers to whoever subscribed; the platform cannot know who did.
        return self.broker.connection is not None and not self.broker.connection.closed

    def publish(self, topic: str, payload: bytes, qos: int, retain: bool = False) -> None:
        if self.deliverable(topic):
            assert self.broker.connection is not None
            self.broker.connection.publish(topic, payload, qos, retain)

    @staticmethod
    def ack(broker: ExternalBroker, receipts: Iterable[Receipt]) -> None:
        for receipt in receipts:
            # A packet id means something only on the connection it came on; after a
            # reconnect the broker sends the message again.
            if receipt.origin is broker.connection and broker.connection is not None:
                broker.connection.acknowledge(receipt.packet_id, receipt.qos)

    def acknowledge(self, receipts: Iterable[Receipt], reason: int) -> None:
        self.ack(self.broker, receipts)

    async def drain(self) -> None:
        connection = self.broker.connection
        if connection is not None and not connection.closed:
            try:
                await connection.writer.drain()
            except (ConnectionError, OSError):
                return

    def fail(self, text: str) -> None:
        # Not acknowledged, and the connection is renewed: the broker sends it again.
        self.broker.status.error("store_failed", text)
        if self.broker.connection is not None:
            self.broker.connection.writer.close()

    def session_closed(self, code: int, reason: str) -> None:
        bridge = self.broker.bridges.get(self.key)
        if code != 1000 and bridge is not None and bridge.outlet is self:
            del self.broker.bridges[self.key]  # replaced or revoked; heard from again, reopened
            self.broker.status.clients = len(self.broker.bridges)
