"""The platform's own connection to an external broker (MQTT 3.1.1): connect with its
credentials and a lasting session, subscribe, publish, and acknowledge each message only
when told to, which is what lets a QoS 1 message wait for the disk before its PUBACK."""

from __future__ import annotations

import asyncio
import contextlib
import ssl
from dataclasses import dataclass
from typing import TypeVar
from urllib.parse import urlsplit

from twinlink.domain.errors import TwinlinkError
from twinlink.ingest.mqtt import packets as mq

READ_BYTES = 256 * 1024
HANDSHAKE_TIMEOUT_S = 10.0
_P = TypeVar("_P", mq.ConnAck, mq.SubAck)


class BrokerError(TwinlinkError):
    """The broker cannot be used as configured; the message says which setting to change."""


class BrokerRefused(BrokerError):
    """The broker answered CONNECT with a refusal (credentials, client id): retrying with the
    same settings cannot help."""


@dataclass(frozen=True, slots=True)
class BrokerAddress:
    host: str
    port: int
    tls: bool

    @classmethod
    def parse(cls, url: str) -> BrokerAddress:
        """`mqtt://host:port` or `mqtts://host:port` (ports 1883 and 8883 by default)."""
        parts = urlsplit(url)
        # The messages name the host, never the whole URL: it may hold a password.
        if parts.scheme not in ("mqtt", "mqtts") or not parts.hostname:
            raise BrokerError("TWINLINK_MQTT_BROKER_URL: use mqtt://host:port or mqtts://host:port")
        tls = parts.scheme == "mqtts"
        try:
            port = parts.port or (8883 if tls else 1883)
        except ValueError as err:
            raise BrokerError(f"TWINLINK_MQTT_BROKER_URL ({parts.hostname}): {err}") from err
        return cls(parts.hostname, port, tls)

    def __str__(self) -> str:
        return f"{'mqtts' if self.tls else 'mqtt'}://{self.host}:{self.port}"


class BrokerConnection:
    """One TCP connection to the broker, after a successful CONNECT."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer
        self.packets = mq.PacketReader(1 << 28, mq.V311)
        self.early: list[mq.Packet] = []  # read while waiting for CONNACK or SUBACK
        self._packet_id = 0

    @classmethod
    async def open(
        cls,
        address: BrokerAddress,
        client_id: str,
        username: str | None,
        password: str | None,
        keep_alive: int,
    ) -> BrokerConnection:
        """Connect with a lasting session (clean session 0): messages that arrive while the
        platform is away wait at the broker, and unacknowledged ones come again."""
        context = ssl.create_default_context() if address.tls else None
        async with asyncio.timeout(HANDSHAKE_TIMEOUT_S):
            reader, writer = await asyncio.open_connection(address.host, address.port, ssl=context)
        connection = cls(reader, writer)
        try:
            writer.write(
                mq.encode_connect(mq.V311, client_id, False, keep_alive, username, password)
            )
            async with asyncio.timeout(HANDSHAKE_TIMEOUT_S):
                connack = await connection._wait_for(mq.ConnAck)
            if connack.reason != mq.SUCCESS:
                raise BrokerRefused(_refusal(address, connack.reason))
        except BaseException:
            await connection.close()
            raise
        return connection

    async def subscribe(self, filters: list[str]) -> None:
        self.writer.write(mq.encode_subscribe(mq.V311, self.next_id(), [(f, 1) for f in filters]))
        async with asyncio.timeout(HANDSHAKE_TIMEOUT_S):
            suback = await self._wait_for(mq.SubAck)
        refused = [f for f, code in zip(filters, suback.codes, strict=False) if code >= 0x80]
        if refused:
            raise BrokerRefused(
                f"the broker refused the subscription to {', '.join(refused)}: allow the "
                "platform's user to read them (the broker's ACL)"
            )

    async def _wait_for(self, kind: type[_P]) -> _P:
        """The next packet of `kind`; the others read meanwhile are kept for `read`."""
        while True:
            data = await self.reader.read(READ_BYTES)
            if not data:
                raise ConnectionError("the broker closed the connection")
            found: _P | None = None
            for packet in self.packets.feed(data):
                if found is None and isinstance(packet, kind):
                    found = packet
                else:
                    self.early.append(packet)
            if found is not None:
                return found

    async def read(self) -> list[mq.Packet]:
        """The packets complete so far (perhaps none); ConnectionError once the broker closed
        the connection."""
        if self.early:
            early, self.early = self.early, []
            return early
        data = await self.reader.read(READ_BYTES)
        if not data:
            raise ConnectionError("the broker closed the connection")
        return self.packets.feed(data)

    def next_id(self) -> int:
        self._packet_id = self._packet_id % 65535 + 1
        return self._packet_id

    def publish(self, topic: str, payload: bytes, qos: int, retain: bool) -> None:
        packet_id = self.next_id() if qos else 0
        self.writer.write(mq.encode_publish(mq.V311, topic, payload, qos, packet_id, retain))

    def acknowledge(self, packet_id: int, qos: int) -> None:
        if not self.writer.is_closing():
            kind = mq.PUBACK if qos == 1 else mq.PUBREC
            self.writer.write(mq.encode_ack(kind, packet_id, mq.V311))

    def ping(self) -> None:
        self.writer.write(mq.PINGREQ_BYTES)

    @property
    def closed(self) -> bool:
        return self.writer.is_closing()

    async def close(self) -> None:
        if not self.writer.is_closing():
            self.writer.write(mq.encode_disconnect(mq.V311))
        self.writer.close()
        with contextlib.suppress(ConnectionError, OSError, ssl.SSLError):
            await self.writer.wait_closed()


def _refusal(address: BrokerAddress, reason: int) -> str:
    if reason in (mq.BAD_CREDENTIALS, mq.NOT_AUTHORIZED):
        return (
            f"{address} refused the platform's credentials: set TWINLINK_MQTT_USERNAME and "
            "TWINLINK_MQTT_PASSWORD to a user of that broker"
        )
    if reason == mq.CLIENT_ID_INVALID:
        return f"{address} refused the client id: set TWINLINK_MQTT_CLIENT_ID"
    return f"{address} refused the connection (CONNACK reason 0x{reason:02x})"
