"""The channel between the server and a worker: length-prefixed MessagePack frames on a socket.

Each frame is a 4-byte big-endian length and a MessagePack map with a type `t`. Sample batches
travel as raw little-endian arrays (int64 times, float64 columns), so a batch of any size is
one frame, copied once each way and never turned into Python objects on the way.

server -> worker: init, data, configure, stop
worker -> server: ready, out, configured, failed, stopped
"""

from __future__ import annotations

import asyncio
import socket
import struct
from typing import Any

import msgspec
import numpy as np

from twinlink.processors.blueprint import Batch

MAX_FRAME = 256 * 1024 * 1024
_LENGTH = struct.Struct(">I")
_encoder = msgspec.msgpack.Encoder()
_decoder = msgspec.msgpack.Decoder()


class ChannelClosed(Exception):
    """The other end went away."""

    # Not a TwinlinkError: control flow between a processor's supervisor and its worker
    # process, which ends the channel (the supervisor restarts the worker); never an answer.


def frame(message: dict[str, Any]) -> bytes:
    body = _encoder.encode(message)
    return _LENGTH.pack(len(body)) + body


def pack_batch(batch: Batch) -> dict[str, Any]:
    return {
        "times": np.ascontiguousarray(batch.times, dtype="<i8").tobytes(),
        "cols": {
            k: np.ascontiguousarray(v, dtype="<f8").tobytes() for k, v in batch.columns.items()
        },
    }


def unpack_batch(message: dict[str, Any]) -> Batch:
    return Batch(
        np.frombuffer(message["times"], dtype="<i8"),
        {k: np.frombuffer(v, dtype="<f8") for k, v in message["cols"].items()},
    )


async def read_frame(reader: asyncio.StreamReader) -> dict[str, Any]:
    try:
        (length,) = _LENGTH.unpack(await reader.readexactly(4))
        if length > MAX_FRAME:
            raise ChannelClosed(f"frame of {length} bytes is over the limit")
        message: dict[str, Any] = _decoder.decode(await reader.readexactly(length))
    except (asyncio.IncompleteReadError, ConnectionError) as err:
        raise ChannelClosed("the worker closed the channel") from err
    except msgspec.DecodeError as err:
        raise ChannelClosed(f"the worker sent an unreadable frame: {err}") from err
    return message


class BlockingChannel:
    """The worker's end: blocking reads and writes on its socket."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock

    def send(self, message: dict[str, Any]) -> None:
        self.sock.sendall(frame(message))

    def receive(self) -> dict[str, Any]:
        (length,) = _LENGTH.unpack(self._exactly(4))
        message: dict[str, Any] = _decoder.decode(self._exactly(length))
        return message

    def _exactly(self, n: int) -> bytes:
        buffer = bytearray(n)
        view = memoryview(buffer)
        got = 0
        while got < n:
            count = self.sock.recv_into(view[got:], n - got)
            if count == 0:
                raise ChannelClosed("the server closed the channel")
            got += count
        return bytes(buffer)
