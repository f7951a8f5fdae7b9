"""A live connection's outbox: bounded, oldest batches dropped first, drops reported, answers
before data, `sent` stamped as a message leaves."""

from __future__ import annotations

import asyncio
from typing import Any

import orjson

from twinlink.domain.samples import SampleBatch
from twinlink.live.outbox import CONTROL_LIMIT, Outbox
from twinlink.live.subscription import Subscription

T0 = 1_732_200_000_000_000_000


def make_batch(n: int = 1, first: int = 0) -> SampleBatch:
    times = [T0 + (first + i) * 1000 for i in range(n)]
    values: list[dict[str, Any]] = [{"i": first + i} for i in range(n)]
    return SampleBatch(1, "rig", "telemetry", times, values, received_ns=T0)


def started(sub_id: str = "a") -> Subscription:
    sub = Subscription(sub_id, 1, "rig", "telemetry")
    sub.started = True
    return sub


def drain(outbox: Outbox) -> list[dict[str, Any]]:
    out = []
    while (message := outbox.take()) is not None:
        out.append(orjson.loads(message))
    return out


def first_values(messages: list[dict[str, Any]]) -> list[int]:
    return [m["samples"][0]["values"]["i"] for m in messages if m["type"] == "samples"]


def test_a_full_outbox_drops_the_oldest_batches_and_says_how_many() -> None:
    outbox, sub = Outbox(capacity=3), started()
    for i in range(10):
        outbox.put_batch(sub, make_batch(2, first=10 * i))
    assert len(outbox) == 3 and outbox.dropped_batches == 7
    messages = drain(outbox)
    assert messages[0] == {"type": "dropped", "sub": "a", "messages": 7, "samples": 14}
    assert first_values(messages[1:]) == [70, 80, 90]  # the newest are kept


def test_drops_are_counted_per_subscription_and_reported_once() -> None:
    outbox, a, b = Outbox(capacity=2), started("a"), started("b")
    for sub in (a, b, a, b, a):
        outbox.put_batch(sub, make_batch())
    messages = drain(outbox)
    dropped = {m["sub"]: m["messages"] for m in messages if m["type"] == "dropped"}
    assert dropped == {"a": 2, "b": 1}
    outbox.put_batch(a, make_batch())
    assert [m["type"] for m in drain(outbox)] == ["samples"]


def test_a_sample_limit_also_bounds_the_queue_but_the_newest_batch_is_always_kept() -> None:
    outbox, sub = Outbox(capacity=100, max_samples=10), started()
    outbox.put_batch(sub, make_batch(6))
    outbox.put_batch(sub, make_batch(6, first=100))
    assert len(outbox) == 1
    outbox.put_batch(sub, make_batch(50, first=200))  # alone over the limit: still sent
    messages = drain(outbox)
    assert messages[0]["type"] == "dropped" and messages[0]["samples"] == 12
    assert first_values(messages) == [200]


def test_answers_go_before_queued_data() -> None:
    outbox, sub = Outbox(capacity=10), started()
    outbox.put_batch(sub, make_batch())
    outbox.put_control({"type": "pong"})
    assert [m["type"] for m in drain(outbox)] == ["pong", "samples"]


def test_data_of_a_subscription_waits_until_its_answer_is_queued() -> None:
    outbox = Outbox(capacity=10)
    sub = Subscription("a", 1, "rig", "telemetry")  # not started yet
    outbox.put_batch(sub, make_batch())
    assert outbox.take() is None
    outbox.put_control({"type": "subscribed", "id": "a"})
    sub.started = True
    assert [m["type"] for m in drain(outbox)] == ["subscribed", "samples"]


def test_nothing_queued_for_an_ended_subscription_is_sent_or_reported() -> None:
    outbox, a, b = Outbox(capacity=2), started("a"), started("b")
    for _ in range(3):
        outbox.put_batch(a, make_batch())
    outbox.forget(a)
    outbox.put_batch(b, make_batch())
    assert [(m["type"], m["sub"]) for m in drain(outbox)] == [("samples", "b")]


def test_sent_is_stamped_when_the_message_is_taken() -> None:
    now = [5]
    outbox, sub = Outbox(capacity=4, clock=lambda: now[0]), started()
    outbox.put_batch(sub, make_batch())
    now[0] = 99
    [message] = drain(outbox)
    assert (message["received"], message["sent"]) == (T0, 99)


async def test_next_message_waits_for_something_to_send() -> None:
    outbox, sub = Outbox(capacity=4), started()
    waiting = asyncio.create_task(outbox.next_message())
    await asyncio.sleep(0)
    assert not waiting.done()
    outbox.put_batch(sub, make_batch())
    message = orjson.loads(await asyncio.wait_for(waiting, 5))
    assert message["type"] == "samples"


async def test_unread_answers_stop_the_reading_of_more_requests() -> None:
    outbox = Outbox(capacity=4)
    for _ in range(CONTROL_LIMIT):
        outbox.put_control({"type": "pong"})
    room = asyncio.create_task(outbox.control_room())
    await asyncio.sleep(0)
    assert not room.done()
    assert outbox.take() is not None
    await asyncio.wait_for(room, 5)
