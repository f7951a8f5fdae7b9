"""The in-process bus: publishing is a dictionary lookup and a few function calls."""

from __future__ import annotations

import logging

from twinlink.bus.base import Handler, Unsubscribe

log = logging.getLogger("twinlink.bus")


class MemoryBus:
    def __init__(self) -> None:
        self._exact: dict[str, list[Handler]] = {}
        self._prefix: dict[str, list[Handler]] = {}

    async def start(self) -> None:
        return None

    async def ready(self) -> bool:
        return True  # nothing outside the process to lose

    async def stop(self) -> None:
        self._exact.clear()
        self._prefix.clear()

    async def publish(self, subject: str, message: object) -> None:
        self.publish_now(subject, message)

    def publish_now(self, subject: str, message: object) -> None:
        """Deliver synchronously (the memory bus needs no await)."""
        for handler in self._exact.get(subject, ()):
            _call(handler, subject, message)
        if self._prefix:
            # A snapshot: a handler may (un)subscribe a prefix while we iterate.
            for prefix, handlers in list(self._prefix.items()):
                if subject.startswith(prefix):
                    for handler in handlers:
                        _call(handler, subject, message)

    def subscribe(self, pattern: str, handler: Handler) -> Unsubscribe:
        if pattern.endswith("*"):
            table, key = self._prefix, pattern[:-1]
        else:
            table, key = self._exact, pattern
        # Copy on write: a handler may unsubscribe while a publish iterates.
        table[key] = [*table.get(key, ()), handler]

        def unsubscribe() -> None:
            handlers = [h for h in table.get(key, ()) if h is not handler]
            if handlers:
                table[key] = handlers
            else:
                table.pop(key, None)

        return unsubscribe


def _call(handler: Handler, subject: str, message: object) -> None:
    try:
        handler(subject, message)
    except Exception:
        log.exception("bus subscriber failed", extra={"event": "bus_handler", "subject": subject})
