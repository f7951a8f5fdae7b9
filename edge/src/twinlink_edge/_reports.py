"""Reported properties on their way to the server, each until its `reported_ack`.

Each `reported` message carries an `id` of the device's choosing. A `reported_ack` (or an
`error`) that echoes it answers that report; one without it answers the oldest report sent on
this connection (the server answers reports in order). Unanswered reports go out again after
a reconnect."""

from __future__ import annotations

import asyncio
from collections import OrderedDict, deque
from typing import Any

from ._protocol import JsonObject, dumps


class ReportError(Exception):
    """The server refused reported properties (the text is its reason)."""


class Reports:
    def __init__(self) -> None:
        self._next_id = 0
        self._items: OrderedDict[int, tuple[str, asyncio.Future[int]]] = OrderedDict()
        self._unsent: deque[int] = deque()
        self._awaiting: deque[int] = deque()  # sent on this connection, in order

    def __len__(self) -> int:
        return len(self._items)

    def add(self, properties: JsonObject, fut: asyncio.Future[int]) -> None:
        self._next_id += 1
        rid = self._next_id
        text = dumps({"type": "reported", "id": rid, "properties": properties})
        self._items[rid] = (text, fut)
        self._unsent.append(rid)

    def rewind(self) -> None:
        """A new connection: every unanswered report goes out again, in order."""
        self._unsent = deque(self._items)
        self._awaiting.clear()

    def next_unsent(self) -> str | None:
        while self._unsent:
            rid = self._unsent.popleft()
            if rid in self._items:
                self._awaiting.append(rid)
                return self._items[rid][0]
        return None

    def _answered(self, msg: JsonObject) -> asyncio.Future[int] | None:
        """The future of the report `msg` answers, forgotten; None when it answers none."""
        rid: Any = msg.get("id")
        if rid not in self._items:
            while self._awaiting and self._awaiting[0] not in self._items:
                self._awaiting.popleft()
            if not self._awaiting:
                return None
            rid = self._awaiting[0]
        if rid in self._awaiting:
            self._awaiting.remove(rid)
        return self._items.pop(rid)[1]

    def acked(self, msg: JsonObject) -> bool:
        fut = self._answered(msg)
        if fut is None:
            return False
        if not fut.done():
            version = msg.get("version")
            fut.set_result(version if isinstance(version, int) else -1)
        return True

    def refused(self, msg: JsonObject) -> bool:
        """An `error` about a report (it names the report's `id`, or `op: reported`)."""
        if msg.get("id") not in self._items and msg.get("op") != "reported":
            return False
        fut = self._answered(msg)
        if fut is None:
            return False
        if not fut.done():
            fut.set_exception(ReportError(str(msg.get("message", "refused"))))
            fut.exception()  # retrieved here: a caller that did not wait is not warned
        return True

    def cancel(self) -> None:
        for _, fut in self._items.values():
            fut.cancel()
        self._items.clear()
        self._unsent.clear()
        self._awaiting.clear()
