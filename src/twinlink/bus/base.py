"""The bus interface. The in-process `MemoryBus` implements it, and `KafkaBus` (bus/kafka/)
across nodes.

Subjects are dotted names: `samples.{twin_id}.{stream}` carries `SampleBatch`es (a batch, not a
sample, is the unit), `commands.{twin_id}` and `properties.{twin_id}` carry command and property
events. A subscription names a subject or a prefix ending in `.*`
(`samples.7.*` is every stream of twin 7, `samples.*` every stream of every twin).

Handlers are plain callables run on the event loop: they must not block and should hand work
to a queue of their own (a slow subscriber must never slow a publisher). A handler that raises
is logged and stays subscribed, so one bad subscriber cannot break the others.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

Handler = Callable[[str, object], None]
Unsubscribe = Callable[[], None]


def samples_subject(twin_id: int, stream: str) -> str:
    return f"samples.{twin_id}.{stream}"


class Bus(Protocol):
    async def start(self) -> None: ...

    async def stop(self) -> None: ...

    async def ready(self) -> bool:
        """Whether the bus can carry messages now (for /readyz); may wait on the network,
        and the caller bounds how long."""

    async def publish(self, subject: str, message: object) -> None:
        """Hand `message` to every current subscriber of `subject`."""

    def subscribe(self, pattern: str, handler: Handler) -> Unsubscribe:
        """Call `handler(subject, message)` for each message on a matching subject; the
        returned callable ends the subscription."""
