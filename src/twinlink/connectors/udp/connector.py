"""UDP datasources, as in Tvilling digital: a listener on a configured address and port turns
each datagram into samples (a `struct` byte format, HBM catman's records, or JSON) and hands
them to the platform as the connector's device.

The hot path is `receive`, called by the event loop for each datagram: check the sender,
decode with a precompiled `struct.Struct`, append to the pending samples. Sending happens
beside it, in `run`: whatever arrived within `batch_window_ms` (or `batch_max_samples`) goes
to the platform as one batch, so a high datagram rate never means a batch per datagram.
UDP cannot slow a sender down: when the platform falls behind, datagrams beyond
`MAX_PENDING` samples are dropped and counted.
"""

from __future__ import annotations

import asyncio
import errno
import ipaddress
import logging
import socket
import time
from typing import Any

from pydantic import BaseModel

from twinlink.connectors.base import Connector, ConnectorError, ConnectorHost, ConnectorStatus
from twinlink.connectors.udp.config import UdpConfig
from twinlink.connectors.udp.format import (
    CatmanDecoder,
    Clock,
    DecodeError,
    JsonDecoder,
    Report,
    Sample,
    StructDecoder,
)

log = logging.getLogger("twinlink.connectors.udp")

MAX_PENDING = 100_000  # samples waiting for the platform; beyond, datagrams are dropped
RECEIVE_BUFFER = 4 * 2**20  # asked of the kernel (it may grant less) to ride out bursts
_SENDERS_REMEMBERED = 4096

Decoder = StructDecoder | JsonDecoder


def build_decoder(config: UdpConfig, report: Report) -> Decoder:
    clock = Clock(config.time_unit, config.time_origin)
    skip_nan = config.nan == "skip"
    if config.format == "catman":
        return CatmanDecoder(
            config.channels, config.time_channel, clock, config.single, skip_nan, report
        )
    if config.format == "json":
        names = [name for name in config.channels if name is not None]
        return JsonDecoder(names, config.time_channel or "time", clock, report)
    assert config.byte_format is not None  # checked by UdpConfig
    return StructDecoder(
        config.byte_format, config.channels, config.time_channel, clock, skip_nan, report
    )


class SenderFilter:
    """Whether a source address is one of the allowed ones; answers are remembered, since
    the same few senders send every datagram."""

    def __init__(self, allowed: list[str]) -> None:
        self.networks = [ipaddress.ip_network(entry, strict=False) for entry in allowed]
        self._known: dict[str, bool] = {}

    def allows(self, host: str) -> bool:
        known = self._known.get(host)
        if known is None:
            if len(self._known) >= _SENDERS_REMEMBERED:  # a spoofing flood: start again
                self._known.clear()
            known = self._known[host] = self._check(host)
        return known

    def _check(self, host: str) -> bool:
        try:
            address = ipaddress.ip_address(host.partition("%")[0])
        except ValueError:
            return False
        if isinstance(address, ipaddress.IPv6Address) and address.ipv4_mapped is not None:
            address = address.ipv4_mapped  # an IPv4 sender on a dual-stack socket
        return any(address in network for network in self.networks)


class UdpStatus(ConnectorStatus):
    """The common status, plus the address actually listened on (the port, when 0 was
    configured). `messages` counts the datagrams read."""

    __slots__ = ("address",)

    def __init__(self) -> None:
        super().__init__()
        self.address: str | None = None

    def view(self) -> dict[str, Any]:
        return {**super().view(), "address": self.address}


class _Receiver(asyncio.DatagramProtocol):
    def __init__(self, connector: UdpConnector) -> None:
        self.receive = connector.receive
        self.closed: asyncio.Future[None] = asyncio.get_running_loop().create_future()

    def datagram_received(self, data: bytes, addr: tuple[str | Any, int]) -> None:
        self.receive(data, addr[0])

    def error_received(self, exc: Exception) -> None:
        log.warning("UDP socket error: %s", exc, extra={"event": "udp_socket_error"})

    def connection_lost(self, exc: Exception | None) -> None:
        if not self.closed.done():
            self.closed.set_result(None)


class UdpConnector(Connector):
    """Listens for UDP datagrams on an address and port and maps each to samples: by a
    Python struct byte format with named channels, by HBM catman's record layout, or as
    one JSON object. Only the allowed senders are heard; malformed datagrams are counted."""

    kind = "udp"
    Config = UdpConfig

    def __init__(self, name: str, config: BaseModel, host: ConnectorHost) -> None:
        if not isinstance(config, UdpConfig):
            raise TypeError("a UdpConnector takes a UdpConfig")
        super().__init__(name, config, host)
        self.settings = config
        self.status: UdpStatus = UdpStatus()
        self.decoder = build_decoder(config, self.status.error)
        self.senders = SenderFilter(config.allowed_senders)
        self.address: tuple[str, int] | None = None
        self._transport: asyncio.DatagramTransport | None = None
        self._receiver: _Receiver | None = None
        self._pending: list[Sample] = []
        self._wake = asyncio.Event()  # the first sample of a batch is pending
        self._full = asyncio.Event()  # a whole batch is pending

    # -- life ------------------------------------------------------------------------------

    async def prepare(self) -> None:
        host, port = self.settings.host, self.settings.port
        loop = asyncio.get_running_loop()
        # The socket is bound here, not by the event loop, so the error is the system's own
        # (uvloop words a port in use as "could not bind", without its errno).
        family = socket.AF_INET6 if ":" in host else socket.AF_INET
        sock = socket.socket(family, socket.SOCK_DGRAM)
        try:
            sock.bind((host, port))
        except OSError as err:
            sock.close()
            hint = " (another program or connector has it)" if err.errno == errno.EADDRINUSE else ""
            raise ConnectorError(
                f"cannot listen for UDP on {host}:{port}: {err.strerror or err}{hint}"
            ) from err
        transport, receiver = await loop.create_datagram_endpoint(
            lambda: _Receiver(self), sock=sock
        )
        self._transport, self._receiver = transport, receiver
        sock = transport.get_extra_info("socket")
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
        except OSError:  # the default buffer works, only with less room for bursts
            log.info("could not enlarge the UDP receive buffer")
        bound = transport.get_extra_info("sockname")
        self.address = (str(bound[0]), int(bound[1]))
        self.status.address = f"{bound[0]}:{bound[1]}"
        self.decoder.reset()
        # Listening and its device connected when start() returns, so the answer to the
        # person who created it says so.
        await self.open_link()
        self.status.set_state("listening")

    async def run(self) -> None:
        window = self.settings.batch_window_ms / 1000
        try:
            while True:
                await self._wake.wait()
                if window and not self._full.is_set():
                    try:
                        async with asyncio.timeout(window):
                            await self._full.wait()
                    except TimeoutError:
                        pass
                await self._flush()
        finally:
            # Stopping: no more datagrams, and those already read still reach the platform.
            self._close_socket()
            if self._pending:
                await self._flush()

    async def cleanup(self) -> None:
        self._close_socket()
        if self._receiver is not None:
            # The socket closes on the next loop turn; wait, so the port is free on return.
            await self._receiver.closed
            self._receiver = None

    def _close_socket(self) -> None:
        if self._transport is not None:
            self._transport.close()
            self._transport = None

    # -- the hot path ----------------------------------------------------------------------

    def receive(self, data: bytes, sender: str) -> None:
        """One datagram from `sender` (its IP address)."""
        arrival_ns = time.time_ns()
        status = self.status
        if not self.senders.allows(sender):
            status.error("refused_sender", f"a datagram from {sender}, not in allowed_senders")
            return
        pending = self._pending
        if len(pending) >= MAX_PENDING:
            status.error("overflow", f"the platform is behind: a datagram from {sender} dropped")
            return
        try:
            samples = self.decoder.decode(data, arrival_ns)
        except DecodeError as err:
            status.error(err.kind, f"{err.text} (from {sender})")
            return
        except Exception as err:  # a decoder bug must not stop the listener
            log.exception("decoding a datagram failed", extra={"event": "udp_decode_failed"})
            status.error("decode_failed", f"{type(err).__name__}: {err} (from {sender})")
            return
        status.received(arrival_ns)
        if samples:
            pending += samples
            if not self._wake.is_set():
                self._wake.set()
            if len(pending) >= self.settings.batch_max_samples:
                self._full.set()

    async def _flush(self) -> None:
        pending, self._pending = self._pending, []
        self._wake.clear()
        self._full.clear()
        size = self.settings.batch_max_samples
        for start in range(0, len(pending), size):
            await self._send(pending[start : start + size])

    async def _send(self, samples: list[Sample]) -> None:
        try:
            await self.send_samples(samples, self.settings.stream)
        except Exception as err:  # the next batch may well go through: keep listening
            log.exception("handing a batch over failed", extra={"event": "udp_send_failed"})
            self.status.error("send_failed", f"{len(samples)} samples lost: {err}")
