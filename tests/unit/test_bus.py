"""The in-memory bus: exact and prefix subscriptions, unsubscribing, failing handlers."""

from __future__ import annotations

import logging

import pytest

from twinlink.bus import Handler, MemoryBus, samples_subject

Seen = list[tuple[str, str, object]]


def recorder(seen: Seen, tag: str) -> Handler:
    def handler(subject: str, message: object) -> None:
        seen.append((tag, subject, message))

    return handler


def test_samples_subject() -> None:
    assert samples_subject(7, "telemetry") == "samples.7.telemetry"


async def test_exact_subscription_gets_only_its_subject() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.7.telemetry", recorder(seen, "a"))
    await bus.publish("samples.7.telemetry", 1)
    await bus.publish("samples.7.imu", 2)
    await bus.publish("samples.70.telemetry", 3)
    await bus.publish("samples.7", 4)
    assert seen == [("a", "samples.7.telemetry", 1)]


async def test_prefix_subscription_of_one_twin() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.7.*", recorder(seen, "twin7"))
    for subject in ["samples.7.telemetry", "samples.7.imu", "samples.70.telemetry", "samples.7"]:
        await bus.publish(subject, subject)
    await bus.publish("commands.7", "cmd")
    assert [s for _, s, _ in seen] == ["samples.7.telemetry", "samples.7.imu"]


async def test_prefix_subscription_of_every_twin() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.*", recorder(seen, "all"))
    for subject in ["samples.1.t", "samples.22.imu", "commands.1", "properties.1", "samplesx.1"]:
        await bus.publish(subject, None)
    assert [s for _, s, _ in seen] == ["samples.1.t", "samples.22.imu"]


async def test_the_handler_gets_subject_and_the_same_message_object() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.*", recorder(seen, "p"))
    message = {"payload": [1, 2]}
    await bus.publish("samples.3.t", message)
    assert seen[0][1] == "samples.3.t"
    assert seen[0][2] is message


async def test_every_matching_subscriber_gets_each_message_in_publish_order() -> None:
    bus = MemoryBus()
    seen: Seen = []
    bus.subscribe("samples.7.t", recorder(seen, "exact"))
    bus.subscribe("samples.7.*", recorder(seen, "twin"))
    bus.subscribe("samples.*", recorder(seen, "all"))
    bus.subscribe("samples.7.t", recorder(seen, "exact2"))
    for i in range(3):
        await bus.publish("samples.7.t", i)
    # messages in publish order; each reaches every subscriber before the next is published
    assert [m for _, _, m in seen] == [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2]
    # exact subscribers first, in subscription order, then the prefixes
    assert [t for t, _, _ in seen[:4]] == ["exact", "exact2", "twin", "all"]


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


async def test_the_same_handler_subscribed_twice_is_called_twice() -> None:
    bus = MemoryBus()
    seen: Seen = []
    handler = recorder(seen, "h")
    bus.subscribe("samples.*", handler)
    bus.subscribe("samples.1.*", handler)
    await bus.publish("samples.1.t", 1)
    assert len(seen) == 2


async def test_unsubscribe_ends_only_that_subscription() -> None:
    bus = MemoryBus()
    seen: Seen = []
    stop_a = bus.subscribe("samples.1.t", recorder(seen, "a"))
    bus.subscribe("samples.1.t", recorder(seen, "b"))
    stop_p = bus.subscribe("samples.*", recorder(seen, "p"))
    bus.subscribe("samples.*", recorder(seen, "q"))
    stop_a()
    stop_p()
    await bus.publish("samples.1.t", 1)
    assert [t for t, _, _ in seen] == ["b", "q"]


async def test_unsubscribe_twice_and_after_the_last_handler_is_harmless() -> None:
    bus = MemoryBus()
    seen: Seen = []
    stop = bus.subscribe("samples.*", recorder(seen, "a"))
    stop()
    stop()
    await bus.publish("samples.1.t", 1)
    assert seen == []
    bus.subscribe("samples.*", recorder(seen, "b"))
    await bus.publish("samples.1.t", 2)
    assert seen == [("b", "samples.1.t", 2)]


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


async def test_a_raising_handler_is_logged_and_does_not_stop_the_others(
    caplog: pytest.LogCaptureFixture,
) -> None:
    bus = MemoryBus()
    seen: Seen = []

    def broken(subject: str, message: object) -> None:
        raise ValueError("subscriber bug")

    bus.subscribe("samples.1.t", broken)
    bus.subscribe("samples.1.t", recorder(seen, "exact"))
    bus.subscribe("samples.*", broken)
    bus.subscribe("samples.*", recorder(seen, "prefix"))
    with caplog.at_level(logging.ERROR, logger="twinlink.bus"):
        await bus.publish("samples.1.t", 1)
    assert [t for t, _, _ in seen] == ["exact", "prefix"]
    failures = [r for r in caplog.records if r.name == "twinlink.bus"]
    assert len(failures) == 2
    for record in failures:
        assert record.levelno == logging.ERROR
        assert record.getMessage() == "bus subscriber failed"
        assert record.subject == "samples.1.t"  # type: ignore[attr-defined]
        assert record.event == "bus_handler"  # type: ignore[attr-defined]
        assert record.exc_info is not None
        assert isinstance(record.exc_info[1], ValueError)


async def test_a_raising_handler_stays_subscribed(caplog: pytest.LogCaptureFixture) -> None:
    bus = MemoryBus()
    calls: list[object] = []

    def flaky(subject: str, message: object) -> None:
        calls.append(message)
        if message == 1:
            raise RuntimeError("first time only")

    bus.subscribe("samples.*", flaky)
    with caplog.at_level(logging.ERROR, logger="twinlink.bus"):
        await bus.publish("samples.1.t", 1)
        await bus.publish("samples.1.t", 2)
    assert calls == [1, 2]
    assert len([r for r in caplog.records if r.name == "twinlink.bus"]) == 1


async def test_stop_drops_every_subscription() -> None:
    bus = MemoryBus()
    seen: Seen = []
    await bus.start()
    bus.subscribe("samples.1.t", recorder(seen, "a"))
    bus.subscribe("samples.*", recorder(seen, "b"))
    await bus.stop()
    await bus.publish("samples.1.t", 1)
    assert seen == []
