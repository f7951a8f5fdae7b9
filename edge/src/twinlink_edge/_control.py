"""The device's messages to the server besides batches and reports: command answers
(`delivered`, `result`) and the pings of round trips, sent in the order they were queued.

A round trip sends a `ping` after everything queued before it and waits for its `pong`. The
server handles a connection's messages in order and sends its own in order (docs/protocol.md,
"Order"), so by then it has every answer queued before, and the device has read everything
the server sent before the pong, such as the commands queued for it, which follow the
welcome. Loop-bound: every method runs on the device's event loop."""

from __future__ import annotations

import asyncio
from collections import deque
from typing import Callable, Union

from ._protocol import dumps

PING = dumps({"type": "ping"})

# A message as JSON text, or a round trip waiting for its ping to go out.
Item = Union[str, "asyncio.Future[None]"]


class ControlQueue:
    def __init__(self, wake: Callable[[], None]) -> None:
        self._wake = wake  # there is something to send
        self._items: deque[Item] = deque()
        self.unconfirmed = False  # messages queued since the last round trip began

    def __bool__(self) -> bool:
        return bool(self._items)

    def put(self, text: str) -> None:
        self._items.append(text)
        self.unconfirmed = True
        self._wake()

    def next(self) -> Item | None:
        """The oldest item to send (its text: `text_of`); None when there is none."""
        while self._items:
            item = self._items.popleft()
            if isinstance(item, str) or not item.done():  # skip a round trip given up
                return item
        return None

    def put_back(self, item: Item) -> None:
        """`item` could not be sent: it goes first next time."""
        self._items.appendleft(item)

    def again(self, round_trips: list[asyncio.Future[None]]) -> None:
        """Round trips whose ping was lost with its connection: after what waits now."""
        self._items.extend(round_trips)

    @staticmethod
    def text_of(item: Item) -> str:
        return item if isinstance(item, str) else PING

    async def round_trip(self, timeout: float | None) -> None:
        """Queue a ping and wait for its pong; `TimeoutError` after `timeout` seconds."""
        fut: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self._items.append(fut)
        self.unconfirmed = False
        self._wake()
        try:
            await asyncio.wait_for(fut, timeout)
        except asyncio.TimeoutError:
            self.unconfirmed = True
            raise TimeoutError(f"no answer to a ping after {timeout} s") from None
