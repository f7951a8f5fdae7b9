"""The live hub on the real MemoryBus: one bus subscription per watched (twin, stream),
counted by its live subscriptions, and each batch fanned out to every watching outbox."""

from __future__ import annotations

import orjson

from twinlink.bus import MemoryBus, samples_subject
from twinlink.domain.samples import SampleBatch
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.subscription import Subscription

T0 = 1_732_200_000_000_000_000


def make_batch(twin_id: int = 1, stream: str = "telemetry") -> SampleBatch:
    return SampleBatch(twin_id, "rig", stream, [T0], [{"x": 1.0}], received_ns=T0)


def started(sub_id: str, twin_id: int = 1, stream: str = "telemetry") -> Subscription:
    sub = Subscription(sub_id, twin_id, "rig", stream)
    sub.started = True
    return sub


def bus_handlers(bus: MemoryBus, twin_id: int, stream: str) -> int:
    return len(bus._exact.get(samples_subject(twin_id, stream), ()))


def taken(outbox: Outbox) -> list[str]:
    out = []
    while (message := outbox.take()) is not None:
        out.append(orjson.loads(message)["sub"])
    return out


def test_one_bus_subscription_per_stream_until_the_last_watcher_leaves() -> None:
    bus = MemoryBus()
    hub = LiveHub(bus)
    a, b, other = started("a"), started("b"), started("c", stream="events")
    for sub in (a, b, other):
        hub.add(sub, Outbox(8))
    assert hub.streams == 2 and hub.watchers(1, "telemetry") == 2
    assert bus_handlers(bus, 1, "telemetry") == 1 and bus_handlers(bus, 1, "events") == 1
    hub.remove(a)
    assert bus_handlers(bus, 1, "telemetry") == 1 and hub.watchers(1, "telemetry") == 1
    hub.remove(a)  # twice is harmless and does not count down again
    assert hub.watchers(1, "telemetry") == 1
    hub.remove(b)
    assert bus_handlers(bus, 1, "telemetry") == 0 and hub.streams == 1
    hub.add(a, Outbox(8))  # a stream watched again subscribes again
    assert bus_handlers(bus, 1, "telemetry") == 1


def test_batches_reach_every_watcher_of_their_stream_only() -> None:
    bus = MemoryBus()
    hub = LiveHub(bus)
    first, second = Outbox(8), Outbox(8)
    hub.add(started("a"), first)
    hub.add(started("b"), first)
    hub.add(started("c"), second)
    hub.add(started("d", twin_id=2), second)
    bus.publish_now(samples_subject(1, "telemetry"), make_batch())
    bus.publish_now(samples_subject(1, "events"), make_batch(stream="events"))
    bus.publish_now(samples_subject(1, "telemetry"), "not a batch")
    assert taken(first) == ["a", "b"] and taken(second) == ["c"]


def test_a_full_outbox_does_not_stop_delivery_to_others() -> None:
    bus = MemoryBus()
    hub = LiveHub(bus)
    slow, fast = Outbox(2), Outbox(1000)
    hub.add(started("slow"), slow)
    hub.add(started("fast"), fast)
    for _ in range(500):
        bus.publish_now(samples_subject(1, "telemetry"), make_batch())
    assert len(slow) == 2 and slow.dropped_batches == 498
    assert len(taken(fast)) == 500


def test_close_ends_every_bus_subscription() -> None:
    bus = MemoryBus()
    hub = LiveHub(bus)
    hub.add(started("a"), Outbox(8))
    hub.add(started("b", twin_id=2), Outbox(8))
    hub.close()
    assert hub.streams == 0 and not bus._exact
