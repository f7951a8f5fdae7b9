"""Live streaming to clients: the hub between the bus and the live WebSocket connections,
and each connection's subscriptions and bounded outgoing queue (docs/protocol.md)."""

from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.session import LiveSession
from twinlink.live.subscription import Subscription

__all__ = ["LiveHub", "LiveSession", "Outbox", "Subscription"]
