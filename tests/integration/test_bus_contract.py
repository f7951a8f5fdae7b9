"""The bus contract, run on each implementation: the in-process MemoryBus and the KafkaBus on
the tests' real broker (tests/integration/_kafka.py). What only the memory bus does (delivery
inside `publish`, the very object handed over, `publish_now`, (un)subscribing while a message
is being delivered) is in tests/unit/test_bus.py.

Kafka hands messages over on its reader task, after `publish` returns: a test awaits
`delivered(bus)` before it looks, which for Kafka waits until the node has read everything
published so far. Twins are partitions of their own there, so the order of messages of two
twins is compared as sets; one twin's order is kept by both.
"""

from __future__ import annotations

import logging
import secrets
from collections.abc import AsyncIterator

import pytest

from tests.integration._kafka import KafkaBroker, kafka
from twinlink.bus import Bus, Handler, MemoryBus
from twinlink.bus.kafka import KafkaBus

pytestmark = pytest.mark.integration
__all__ = ["kafka"]

Seen = list[tuple[str, str, object]]


def recorder(seen: Seen, tag: str) -> Handler:
    def handler(subject: str, message: object) -> None:
        seen.append((tag, subject, message))

    return handler


def kafka_bus(broker: KafkaBroker) -> KafkaBus:
    # Topics of its own per test: nothing another test published reaches it.
    return KafkaBus(broker.bootstrap, topic_prefix=f"t{secrets.token_hex(4)}", partitions=2)


async def delivered(bus: Bus) -> None:
    if isinstance(bus, KafkaBus):
        await bus.caught_up()


@pytest.fixture(params=["memory", "kafka"])
async def bus(request: pytest.FixtureRequest, kafka: KafkaBroker) -> AsyncIterator[Bus]:
    implementation: Bus = MemoryBus() if request.param == "memory" else kafka_bus(kafka)
    await implementation.start()
    try:
        yield implementation
    finally:
        await implementation.stop()


async def test_exact_subscription_gets_only_its_subject(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.7.telemetry", recorder(seen, "a"))
    await bus.publish("samples.7.telemetry", 1)
    await bus.publish("samples.7.imu", 2)
    await bus.publish("samples.70.telemetry", 3)
    await bus.publish("samples.7", 4)
    await delivered(bus)
    assert seen == [("a", "samples.7.telemetry", 1)]


async def test_prefix_subscription_of_one_twin(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.7.*", recorder(seen, "twin7"))
    for subject in ["samples.7.telemetry", "samples.7.imu", "samples.70.telemetry", "samples.7"]:
        await bus.publish(subject, subject)
    await bus.publish("commands.7", "cmd")
    await delivered(bus)
    assert [s for _, s, _ in seen] == ["samples.7.telemetry", "samples.7.imu"]


async def test_prefix_subscription_of_every_twin(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.*", recorder(seen, "all"))
    for subject in ["samples.1.t", "samples.22.imu", "commands.1", "properties.1", "samplesx.1"]:
        await bus.publish(subject, None)
    await delivered(bus)
    assert sorted(s for _, s, _ in seen) == ["samples.1.t", "samples.22.imu"]


async def test_every_family_of_subjects_is_carried(bus: Bus) -> None:
    seen: Seen = []
    subjects = ["samples.3.t", "commands.3", "command-results.3", "properties.3"]
    subjects += ["processors.3", "anything.else", "plain"]
    for subject in subjects:
        bus.subscribe(subject, recorder(seen, subject))
    for subject in subjects:
        await bus.publish(subject, {"subject": subject, "n": [1, 2.5, True, None, "x"]})
    await delivered(bus)
    assert sorted(seen) == sorted(
        (s, s, {"subject": s, "n": [1, 2.5, True, None, "x"]}) for s in subjects
    )


async def test_every_matching_subscriber_gets_each_message_in_publish_order(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.7.t", recorder(seen, "exact"))
    bus.subscribe("samples.7.*", recorder(seen, "twin"))
    bus.subscribe("samples.*", recorder(seen, "all"))
    bus.subscribe("samples.7.t", recorder(seen, "exact2"))
    for i in range(3):
        await bus.publish("samples.7.t", i)
    await delivered(bus)
    # messages in publish order; each reaches every subscriber before the next is handed over
    assert [m for _, _, m in seen] == [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2]
    # exact subscribers first, in subscription order, then the prefixes
    assert [t for t, _, _ in seen[:4]] == ["exact", "exact2", "twin", "all"]


async def test_one_twins_messages_keep_their_order_across_streams(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.5.*", recorder(seen, "twin5"))
    bus.subscribe("samples.6.*", recorder(seen, "twin6"))
    for i in range(40):
        await bus.publish(f"samples.5.{'ab'[i % 2]}", i)
        await bus.publish(f"samples.6.{'cd'[i % 2]}", -i)
    await delivered(bus)
    assert [m for t, _, m in seen if t == "twin5"] == list(range(40))
    assert [m for t, _, m in seen if t == "twin6"] == [-i for i in range(40)]


async def test_publish_without_subscribers_does_nothing(bus: Bus) -> None:
    await bus.publish("samples.1.t", [1, 2])
    await delivered(bus)


async def test_the_same_handler_subscribed_twice_is_called_twice(bus: Bus) -> None:
    seen: Seen = []
    handler = recorder(seen, "h")
    bus.subscribe("samples.*", handler)
    bus.subscribe("samples.1.*", handler)
    await bus.publish("samples.1.t", 1)
    await delivered(bus)
    assert len(seen) == 2


async def test_unsubscribe_ends_only_that_subscription(bus: Bus) -> None:
    seen: Seen = []
    stop_a = bus.subscribe("samples.1.t", recorder(seen, "a"))
    bus.subscribe("samples.1.t", recorder(seen, "b"))
    stop_p = bus.subscribe("samples.*", recorder(seen, "p"))
    bus.subscribe("samples.*", recorder(seen, "q"))
    stop_a()
    stop_p()
    await bus.publish("samples.1.t", 1)
    await delivered(bus)
    assert [t for t, _, _ in seen] == ["b", "q"]


async def test_unsubscribe_twice_and_after_the_last_handler_is_harmless(bus: Bus) -> None:
    seen: Seen = []
    stop = bus.subscribe("samples.*", recorder(seen, "a"))
    stop()
    stop()
    await bus.publish("samples.1.t", 1)
    await delivered(bus)
    assert seen == []
    bus.subscribe("samples.*", recorder(seen, "b"))
    await bus.publish("samples.1.t", 2)
    await delivered(bus)
    assert seen == [("b", "samples.1.t", 2)]


async def test_a_handler_may_unsubscribe_itself_while_messages_arrive(bus: Bus) -> None:
    seen: Seen = []

    def once(subject: str, message: object) -> None:
        seen.append(("once", subject, message))
        stop()

    stop = bus.subscribe("samples.1.*", once)
    bus.subscribe("samples.1.t", recorder(seen, "after"))
    await bus.publish("samples.1.t", 1)
    await bus.publish("samples.1.t", 2)
    await delivered(bus)
    assert [(t, m) for t, _, m in seen] == [("after", 1), ("once", 1), ("after", 2)]


async def test_a_raising_handler_is_logged_and_does_not_stop_the_others(
    bus: Bus, caplog: pytest.LogCaptureFixture
) -> None:
    seen: Seen = []

    def broken(subject: str, message: object) -> None:
        raise ValueError("subscriber bug")

    bus.subscribe("samples.1.t", broken)
    bus.subscribe("samples.1.t", recorder(seen, "exact"))
    bus.subscribe("samples.*", broken)
    bus.subscribe("samples.*", recorder(seen, "prefix"))
    with caplog.at_level(logging.ERROR, logger="twinlink.bus"):
        await bus.publish("samples.1.t", 1)
        await delivered(bus)
    assert [t for t, _, _ in seen] == ["exact", "prefix"]
    failures = [r for r in caplog.records if r.name == "twinlink.bus"]
    assert [r.getMessage() for r in failures] == ["bus subscriber failed"] * 2
    for record in failures:
        assert record.levelno == logging.ERROR
        assert record.subject == "samples.1.t"  # type: ignore[attr-defined]
        assert record.event == "bus_handler"  # type: ignore[attr-defined]
        assert record.exc_info is not None
        assert isinstance(record.exc_info[1], ValueError)


async def test_a_raising_handler_stays_subscribed(
    bus: Bus, caplog: pytest.LogCaptureFixture
) -> None:
    calls: list[object] = []

    def flaky(subject: str, message: object) -> None:
        calls.append(message)
        if message == 1:
            raise RuntimeError("first time only")

    bus.subscribe("samples.*", flaky)
    with caplog.at_level(logging.ERROR, logger="twinlink.bus"):
        await bus.publish("samples.1.t", 1)
        await bus.publish("samples.1.t", 2)
        await delivered(bus)
    assert calls == [1, 2]
    assert len([r for r in caplog.records if r.name == "twinlink.bus"]) == 1


async def test_stop_drops_every_subscription(bus: Bus) -> None:
    seen: Seen = []
    bus.subscribe("samples.1.t", recorder(seen, "a"))
    bus.subscribe("samples.*", recorder(seen, "b"))
    await bus.stop()
    await bus.start()  # started again: the subscriptions of before are gone
    await bus.publish("samples.1.t", 1)
    await delivered(bus)
    assert seen == []


async def test_a_started_bus_is_ready(bus: Bus) -> None:
    assert await bus.ready()  # what /readyz asks of it
