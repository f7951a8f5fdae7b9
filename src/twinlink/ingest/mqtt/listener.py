"""The embedded MQTT listener: devices connect to `twinlink up` itself (MQTT 3.1.1 and 5.0).

It is not a general-purpose broker: every client is a device, authenticated by its token,
that publishes to its own topics and subscribes to what the platform sends it. Nothing is
forwarded between clients, nothing is retained, and sessions end with the connection
(CONNACK says "no session present", so clients subscribe again on each connect). In
exchange a QoS 1 (or 2) publish is acknowledged only once the platform has handled it: for
telemetry, once its batch is durable in history (docs/decisions/0009-mqtt.md).
"""

from __future__ import annotations

import asyncio
import logging
import time

from twinlink.domain.errors import TwinlinkError
from twinlink.ingest.mqtt import packets as mq
from twinlink.ingest.mqtt.connection import DeviceConnection
from twinlink.ingest.mqtt.platform import Platform
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import TopicScheme

log = logging.getLogger("twinlink.mqtt")

SWEEP_S = 1.0  # how often keep-alives are checked


class ListenerError(TwinlinkError):
    """The listener cannot start as configured (the address is in use, say)."""


class EmbeddedListener:
    def __init__(
        self,
        platform: Platform,
        host: str,
        port: int,
        scheme: TopicScheme,
        status: MqttStatus,
        max_packet_bytes: int,
        reuse_port: bool = False,
    ) -> None:
        self.platform = platform
        # Workers of one `twinlink up --workers N` listen on one port, each with its own socket
        # (SO_REUSEPORT): the kernel spreads the connections between them.
        self.reuse_port = reuse_port
        self.host = host
        self.port = port
        self.scheme = scheme
        self.status = status
        self.max_packet_bytes = max_packet_bytes
        self.connections: set[DeviceConnection] = set()
        self._by_client_id: dict[str, DeviceConnection] = {}
        self._tasks: set[asyncio.Task[None]] = set()
        self._server: asyncio.Server | None = None
        self._sweeper: asyncio.Task[None] | None = None
        self._closing = False

    async def open(self) -> None:
        try:
            self._server = await asyncio.start_server(
                self._serve, self.host, self.port, reuse_port=self.reuse_port or None
            )
        except OSError as err:
            raise ListenerError(
                f"MQTT cannot listen on {self.host}:{self.port}: {err.strerror}; set "
                "TWINLINK_MQTT_PORT to a free port (0: any) or TWINLINK_MQTT_MODE=off"
            ) from err
        self.port = self._server.sockets[0].getsockname()[1]
        self.status.address = f"{self.host}:{self.port}"
        self.status.set_state("listening")
        self._sweeper = asyncio.create_task(self._sweep(), name="mqtt-keepalive")
        log.info("mqtt listening", extra={"event": "mqtt_listening", "port": self.port})

    async def close(self) -> None:
        """Stop listening, end every connection (MQTT 5: "server shutting down") once what it
        sent is stored and acknowledged."""
        self._closing = True
        if self._server is not None:
            self._server.close()
        if self._sweeper is not None:
            self._sweeper.cancel()
        for connection in self.connections:
            connection.shut_down()
        if self._tasks:
            await asyncio.gather(*self._tasks, return_exceptions=True)
        if self._server is not None:
            await self._server.wait_closed()
        self.status.set_state("stopped")

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        if self._closing:  # accepted just before `close`, started after it
            writer.close()
            return
        connection = DeviceConnection(self, reader, writer)
        task = asyncio.current_task()
        assert task is not None
        self._tasks.add(task)
        self.connections.add(connection)
        self.status.clients = len(self.connections)
        try:
            await connection.serve()
        finally:
            self.connections.discard(connection)
            self.status.clients = len(self.connections)
            self._tasks.discard(task)

    def register(self, connection: DeviceConnection) -> None:
        """The connection is accepted under its client id; an older one with the same id ends."""
        old = self._by_client_id.get(connection.client_id)
        self._by_client_id[connection.client_id] = connection
        if old is not None and old is not connection:
            old.take_over()

    def unregister(self, connection: DeviceConnection) -> None:
        if self._by_client_id.get(connection.client_id) is connection:
            del self._by_client_id[connection.client_id]

    async def _sweep(self) -> None:
        """End connections silent for 1.5 times their keep-alive (MQTT 3.1.2-24)."""
        while True:
            await asyncio.sleep(SWEEP_S)
            now = time.monotonic()
            for connection in list(self.connections):
                limit = connection.keep_alive * 1.5
                if limit and now - connection.last_seen > limit:
                    text = f"nothing heard for {limit:.0f} s (keep-alive)"
                    connection.drop(mq.KEEP_ALIVE_TIMEOUT, "keep_alive", text)
