"""Commands that wait until the program takes them, for code that asks for its commands (the
thesis's `receive()`, `twinlink_edge.compat`) instead of registering handlers.

A command waiting here has not been answered at all: the server still has it `pending` and
sends it again after a reconnect. It becomes `delivered` (and `succeeded`) only when the
program takes it; one never taken is answered `failed` when the device closes. Loop-bound:
every method runs on the device's event loop."""

from __future__ import annotations

import asyncio
import contextlib
from collections import OrderedDict
from dataclasses import dataclass
from typing import Union

from ._protocol import JsonObject

CommandId = Union[str, int]

NOT_READ = "not read by the device"  # the error of a command never taken


@dataclass(frozen=True)
class HeldCommand:
    id: CommandId
    name: str
    args: JsonObject
    arrived_ns: int  # device clock


class Inbox:
    def __init__(self) -> None:
        self._held: OrderedDict[CommandId, HeldCommand] = OrderedDict()
        self._arrived: asyncio.Event | None = None  # made on the loop, by the first wait

    def __len__(self) -> int:
        return len(self._held)

    def __contains__(self, cid: object) -> bool:
        return cid in self._held

    def hold(self, command: HeldCommand) -> None:
        self._held[command.id] = command
        if self._arrived is not None:
            self._arrived.set()

    async def wait(self, timeout: float) -> None:
        """Wait up to `timeout` seconds until a command is held."""
        if self._held or timeout <= 0:
            return
        if self._arrived is None:
            self._arrived = asyncio.Event()
        self._arrived.clear()
        with contextlib.suppress(asyncio.TimeoutError):
            await asyncio.wait_for(self._arrived.wait(), timeout)

    def take(self) -> list[HeldCommand]:
        """Every held command, in arrival order; the inbox is empty after."""
        taken = list(self._held.values())
        self._held.clear()
        return taken
