"""twinlink-edge: the device SDK for twinlink.

`AsyncDevice` for asyncio code, `Device` for plain code (it runs the asyncio client in a
background thread), `twinlink_edge.compat` for code written for the NTNU thesis's
`digitalTwinPlt` module."""

from __future__ import annotations

__version__ = "0.1.0"

from ._buffer import Buffer, DiskBuffer, MemoryBuffer
from ._protocol import Ack, Backoff, BufferFull, device_ws_url
from ._reports import ReportError
from .aio import AsyncDevice
from .sync import Device

__all__ = [
    "Ack",
    "AsyncDevice",
    "Backoff",
    "Buffer",
    "BufferFull",
    "Device",
    "DiskBuffer",
    "MemoryBuffer",
    "ReportError",
    "__version__",
    "device_ws_url",
]
