"""What only the in-memory bus does: it delivers inside `publish` (and `publish_now`), hands
over the very object published, and lets a handler (un)subscribe while a message is being
delivered. The contract every bus keeps (exact and prefix subscriptions, order, unsubscribing,
failing handlers, stop) runs on the MemoryBus and the KafkaBus in
tests/integration/test_bus_contract.py."""

from __future__ import annotations

from twinlink.bus import Handler, MemoryBus, samples_subject

Seen = list[tuple[str, str, object]]


def recorder(seen: Seen, tag: str) -> Handler:
    def handler(subject: str, message: object) -> None:
        seen.append((tag, subject, message))

    return handler


def test_samples_subject() -> None:
    assert samples_subject(7, "telemetry") == "samples.7.telemetry"


async def test_the_handler_gets_subject_and_the_same_message_object() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.*", recorder(seen, "p"))
    message = {"payload": [1, 2]}
    await bus.publish("samples.3.t", message)
    assert seen[0][1] == "samples.3.t"
    assert seen[0][2] is message


def test_publish_now_delivers_synchronously() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("a.b", recorder(seen, "x"))
    bus.publish_now("a.b", 1)
    assert seen == [("x", "a.b", 1)]


async def test_publish_without_subscribers_does_nothing() -> None:
    bus = MemoryBus()
    await bus.publish("samples.1.t", object())
    bus.publish_now("samples.1.t", object())


async def test_an_exact_handler_may_unsubscribe_itself_while_publishing() -> None:
    bus = MemoryBus()
    seen: Seen = []

    def once(subject: str, message: object) -> None:
        seen.append(("once", subject, message))
        stop()

    stop = bus.subscribe("samples.1.t", once)
    bus.subscribe("samples.1.t", recorder(seen, "after"))
    await bus.publish("samples.1.t", 1)
    await bus.publish("samples.1.t", 2)
    assert [(t, m) for t, _, m in seen] == [("once", 1), ("after", 1), ("after", 2)]


async def test_a_handler_may_unsubscribe_another_while_publishing() -> None:
    bus = MemoryBus()
    seen: Seen = []

    def first(subject: str, message: object) -> None:
        seen.append(("first", subject, message))
        stop_second()

    bus.subscribe("samples.*", first)
    stop_second = bus.subscribe("samples.*", recorder(seen, "second"))
    await bus.publish("samples.1.t", 1)
    await bus.publish("samples.1.t", 2)
    # the message being delivered still reaches it; the next one does not
    assert [(t, m) for t, _, m in seen] == [("first", 1), ("second", 1), ("first", 2)]


async def test_the_only_prefix_handler_may_unsubscribe_itself_while_publishing() -> None:
    bus = MemoryBus()
    seen: Seen = []

    def once(subject: str, message: object) -> None:
        seen.append(("once", subject, message))
        stop()

    stop = bus.subscribe("samples.*", once)
    bus.subscribe("samples.1.*", recorder(seen, "other"))
    await bus.publish("samples.1.t", 1)
    await bus.publish("samples.1.t", 2)
    assert [(t, m) for t, _, m in seen] == [("once", 1), ("other", 1), ("other", 2)]


async def test_a_handler_may_subscribe_a_new_prefix_while_publishing() -> None:
    bus = MemoryBus()
    seen: Seen = []

    def subscribe_more(subject: str, message: object) -> None:
        seen.append(("first", subject, message))
        if message == 1:
            bus.subscribe("samples.1.*", recorder(seen, "late"))

    bus.subscribe("samples.*", subscribe_more)
    await bus.publish("samples.1.t", 1)
    await bus.publish("samples.1.t", 2)
    assert [(t, m) for t, _, m in seen] == [("first", 1), ("first", 2), ("late", 2)]
