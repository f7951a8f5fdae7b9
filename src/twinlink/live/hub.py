"""The hub between the bus and the live connections.

It holds one bus subscription per (twin, stream) that at least one live client watches, made
when the first client subscribes and ended when the last one leaves. Its bus handler runs in
the publisher's call (on the event loop, during ingest), so it does only what must be done
there: append a reference to the batch to each watching connection's outbox.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from twinlink.bus import Bus, Unsubscribe, samples_subject
from twinlink.domain.samples import SampleBatch
from twinlink.live.outbox import Outbox
from twinlink.live.subscription import Subscription


@dataclass(slots=True, eq=False)
class _Route:
    """The live subscriptions of one (twin, stream) and the bus subscription feeding them."""

    targets: dict[Subscription, Outbox] = field(default_factory=dict)
    unsubscribe: Unsubscribe | None = None

    def deliver(self, subject: str, message: object) -> None:
        if not isinstance(message, SampleBatch):
            return
        for sub, outbox in self.targets.items():
            outbox.put_batch(sub, message)


class LiveHub:
    def __init__(self, bus: Bus) -> None:
        self._bus = bus
        self._routes: dict[tuple[int, str], _Route] = {}

    def add(self, sub: Subscription, outbox: Outbox) -> None:
        """Start delivering `sub`'s stream to `outbox`."""
        route = self._routes.get(sub.key)
        if route is None:
            route = _Route()
            route.unsubscribe = self._bus.subscribe(samples_subject(*sub.key), route.deliver)
            self._routes[sub.key] = route
        route.targets[sub] = outbox

    def remove(self, sub: Subscription) -> None:
        """Stop delivering to `sub`; the last subscription of a stream ends the bus one."""
        route = self._routes.get(sub.key)
        if route is None or route.targets.pop(sub, None) is None:
            return
        if not route.targets:
            del self._routes[sub.key]
            if route.unsubscribe is not None:
                route.unsubscribe()

    def close(self) -> None:
        """End every bus subscription (at shutdown)."""
        routes, self._routes = self._routes, {}
        for route in routes.values():
            route.targets.clear()
            if route.unsubscribe is not None:
                route.unsubscribe()

    @property
    def streams(self) -> int:
        """How many (twin, stream) pairs the hub holds a bus subscription for."""
        return len(self._routes)

    def watchers(self, twin_id: int, stream: str) -> int:
        route = self._routes.get((twin_id, stream))
        return 0 if route is None else len(route.targets)
