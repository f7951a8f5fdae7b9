"""A connector kind: a TCP listener taking one sample per line of text.

    x=1.5 y=-2          two signals, timed when the line arrives
    time=1732200000.25 x=3   a time of its own, in seconds since the epoch (UTC)

Pairs are separated by spaces or commas. Lines read together go to the platform as one batch;
a line that cannot be read is counted as an error and skipped, the connection stays. TCP
slows a sender down when the platform is behind, so nothing is dropped.

A plug-in's whole shape is here: a settings model (`Config`, with ranges on its numbers and
its secret typed `SecretStr`), a `Connector` subclass with `kind` and `Config`, and `prepare`,
`run` and `cleanup`. It is registered by one line in pyproject.toml:

    [project.entry-points."twinlink.connectors"]
    tcp_lines = "twinlink_example_plugins.tcp_lines:TcpLinesConnector"
"""

from __future__ import annotations

import asyncio
import hmac
import logging
import math
import re
import time
from decimal import Decimal, InvalidOperation
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, SecretStr, field_validator

from twinlink.connectors.base import Connector, ConnectorError, ConnectorHost, ConnectorStatus
from twinlink.domain.samples import STREAM_NAME

_SEPARATORS = re.compile(rb"[\s,]+")
log = logging.getLogger("twinlink_example_plugins.tcp_lines")


class TcpLinesConfig(BaseModel):
    """Where to listen, where the samples go, and who may send."""

    model_config = ConfigDict(extra="forbid")

    host: str = Field("127.0.0.1", description="Address to listen on (0.0.0.0: every one).")
    port: int = Field(ge=0, le=65535, description="TCP port (0: any free one, see the status).")
    stream: str = Field("telemetry", description="The stream the samples go to.")
    max_line_bytes: int = Field(
        4096, ge=16, le=1_048_576, description="Longest line; a longer one ends the connection."
    )
    token: SecretStr | None = Field(
        None, description="When set, a client's first line must be this token, or it is let go."
    )

    @field_validator("stream")
    @classmethod
    def _stream(cls, stream: str) -> str:
        if not STREAM_NAME.match(stream):
            raise ValueError(f"a stream name matches {STREAM_NAME.pattern}")
        return stream


class LineError(ValueError):
    """A line that is not `name=value` pairs of numbers."""


def parse_line(line: bytes, arrival_ns: int) -> dict[str, Any]:
    """One sample (`{"time": ns, "values": {...}}`) from one line."""
    values: dict[str, float] = {}
    time_ns = arrival_ns
    for pair in _SEPARATORS.split(line.strip()):
        name, sep, text = pair.decode("utf-8", "replace").partition("=")
        if not sep or not name:
            raise LineError(f"{pair[:40]!r} is not name=value")
        if name == "time":
            time_ns = _epoch_ns(text)
            continue
        try:
            value = float(text)
        except ValueError:
            raise LineError(f"{name}: {text[:40]!r} is not a number") from None
        if not math.isfinite(value):
            raise LineError(f"{name}: {text[:40]!r} is not a finite number")
        values[name] = value
    if not values:
        raise LineError("no values")
    return {"time": time_ns, "values": values}


def _epoch_ns(text: str) -> int:
    try:
        seconds = Decimal(text)
    except InvalidOperation:
        raise LineError(f"time: {text[:40]!r} is not seconds since the epoch") from None
    if not seconds.is_finite() or not 0 <= seconds < 7_258_118_400:  # 1970 to 2200
        raise LineError(f"time: {text[:40]!r} is not a time between 1970 and 2200")
    return int(seconds * 1_000_000_000)


class TcpLinesStatus(ConnectorStatus):
    """The common status, plus the address listened on and the clients connected."""

    __slots__ = ("address", "clients")

    def __init__(self) -> None:
        super().__init__()
        self.address: str | None = None
        self.clients = 0

    def view(self) -> dict[str, Any]:
        return {**super().view(), "address": self.address, "clients": self.clients}


class TcpLinesConnector(Connector):
    """Listens on a TCP port for lines of `name=value` pairs (and an optional `time=` in
    seconds since the epoch), one sample per line."""

    kind = "tcp_lines"
    Config = TcpLinesConfig

    def __init__(self, name: str, config: BaseModel, host: ConnectorHost) -> None:
        if not isinstance(config, TcpLinesConfig):
            raise TypeError("a TcpLinesConnector takes a TcpLinesConfig")
        super().__init__(name, config, host)
        self.settings = config
        self.status: TcpLinesStatus = TcpLinesStatus()
        self._server: asyncio.Server | None = None
        self._clients: set[asyncio.StreamWriter] = set()

    async def prepare(self) -> None:
        host, port = self.settings.host, self.settings.port
        try:
            self._server = await asyncio.start_server(
                self._serve, host, port, limit=self.settings.max_line_bytes + 1
            )
        except OSError as err:
            raise ConnectorError(f"cannot listen on TCP {host}:{port}: {err}") from err
        bound = self._server.sockets[0].getsockname()
        self.status.address = f"{bound[0]}:{bound[1]}"
        await self.open_link()  # the device is connected when start() returns
        self.status.set_state("listening")

    async def run(self) -> None:
        # The server serves each client in a task of its own from `prepare` on; this is the
        # connector's life, until it is stopped (cancelled).
        await asyncio.get_running_loop().create_future()

    async def cleanup(self) -> None:
        if self._server is not None:
            self._server.close()  # the port is free again at once
            self._server = None
        for writer in list(self._clients):
            writer.close()  # their tasks see the end of the stream and finish

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self._clients.add(writer)
        self.status.clients += 1
        try:
            if await self._admitted(reader, writer):
                await self._read(reader)
        except (ConnectionError, asyncio.IncompleteReadError, asyncio.LimitOverrunError):
            pass  # the client left, or sent a token line far too long
        except Exception as err:  # a bug here must not take the listener down
            log.exception("serving a TCP client failed")
            self.status.error("failed", f"{type(err).__name__}: {err}")
        finally:
            self.status.clients -= 1
            self._clients.discard(writer)
            writer.close()

    async def _admitted(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> bool:
        token = self.settings.token
        if token is None:
            return True
        line = (await reader.readuntil(b"\n")).strip()
        if hmac.compare_digest(line, token.get_secret_value().encode()):
            return True
        self.status.error("refused_client", "a client sent no valid token")
        writer.write(b"refused: the first line must be the connector's token\n")
        return False

    async def _read(self, reader: asyncio.StreamReader) -> None:
        pending = b""
        while chunk := await reader.read(65536):
            arrival_ns = time.time_ns()
            lines = (pending + chunk).split(b"\n")
            pending = lines.pop()  # the start of a line still coming
            if len(pending) > self.settings.max_line_bytes:
                self.status.error("line_too_long", f"over {self.settings.max_line_bytes} bytes")
                return
            samples: list[dict[str, Any]] = []
            for line in lines:
                if line.strip():
                    self.status.received(arrival_ns)
                    try:
                        # Lines read together are 1 ns apart, in order, unless they say a time.
                        samples.append(parse_line(line, arrival_ns + len(samples)))
                    except LineError as err:
                        self.status.error("bad_line", str(err))
            if samples:
                await self._send(samples)

    async def _send(self, samples: list[dict[str, Any]]) -> None:
        # Waits until the platform has the batch: meanwhile TCP holds the sender back.
        try:
            await self.send_samples(samples, self.settings.stream)
        except Exception as err:  # the next batch may well go through: keep reading
            log.exception("handing a batch over failed")
            self.status.error("send_failed", f"{len(samples)} samples lost: {err}")
