"""The Kafka bus on a real broker (tests/integration/_kafka.py), with two KafkaBus instances
as two nodes of a cluster: what one publishes, the other's subscribers get, each twin's
batches in order, every value exact. (The contract both buses keep is test_bus_contract.py.)"""

from __future__ import annotations

import asyncio
import logging
import secrets
from collections.abc import AsyncIterator
from dataclasses import dataclass

import orjson
import pytest
from aiokafka import AIOKafkaConsumer, AIOKafkaProducer, TopicPartition
from aiokafka.errors import KafkaConnectionError

from tests.conftest import free_port
from tests.integration._kafka import KafkaBroker, kafka
from twinlink.bus import samples_subject
from twinlink.bus.kafka import KafkaBus, KafkaBusError, UnencodableMessageError
from twinlink.bus.kafka import bus as kafka_bus_module
from twinlink.domain.samples import SampleBatch, Value
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.subscription import Subscription

pytestmark = pytest.mark.integration
__all__ = ["kafka"]

I64_MIN, I64_MAX = -(2**63), 2**63 - 1


@dataclass
class Nodes:
    a: KafkaBus
    b: KafkaBus
    prefix: str


@pytest.fixture
async def nodes(kafka: KafkaBroker) -> AsyncIterator[Nodes]:
    """Two buses on one broker and one set of topics, as two twinlink nodes would be."""
    prefix = f"n{secrets.token_hex(4)}"
    a = KafkaBus(kafka.bootstrap, topic_prefix=prefix, partitions=4, client_id="node-a")
    b = KafkaBus(kafka.bootstrap, topic_prefix=prefix, partitions=4, client_id="node-b")
    await a.start()
    try:
        await b.start()
        try:
            yield Nodes(a, b, prefix)
        finally:
            await b.stop()
    finally:
        await a.stop()


def batch(twin_id: int, stream: str, values: list[dict[str, Value]], seq: int = 1) -> SampleBatch:
    times = [1_700_000_000_000_000_000 + i for i in range(len(values))]
    return SampleBatch(twin_id, f"twin-{twin_id}", stream, times, values, 1, "device:d1", seq)


async def test_a_batch_published_on_one_node_reaches_the_subscribers_of_both(nodes: Nodes) -> None:
    seen: list[tuple[str, str, object]] = []
    nodes.a.subscribe("samples.*", lambda s, m: seen.append(("a", s, m)))
    nodes.b.subscribe("samples.7.*", lambda s, m: seen.append(("b", s, m)))
    sent = batch(7, "telemetry", [{"angle": 0.5}, {"angle": 0.25}])
    await nodes.a.publish(samples_subject(7, "telemetry"), sent)
    await nodes.a.caught_up()
    await nodes.b.caught_up()
    assert sorted(seen, key=lambda x: x[0]) == [
        ("a", "samples.7.telemetry", sent),
        ("b", "samples.7.telemetry", sent),
    ]
    assert seen[0][2] is not sent  # each node decodes its own copy


async def test_values_times_and_sequence_numbers_stay_exact(nodes: Nodes) -> None:
    got: list[object] = []
    nodes.b.subscribe("samples.3.exact", lambda s, m: got.append(m))
    values: list[dict[str, Value]] = [
        {"big": I64_MAX, "small": I64_MIN, "near": 2**53 + 1},
        {"float": 1.0, "int": 1, "flag": True, "off": False, "text": "ünïcode"},
        {"tiny": 5e-324, "huge": 1.7976931348623157e308, "neg": -0.0},
    ]
    sent = SampleBatch(3, "exact", "exact", [I64_MIN, 0, I64_MAX], values, I64_MAX, "", I64_MAX)
    await nodes.a.publish("samples.3.exact", sent)
    await nodes.b.caught_up()
    assert got == [sent]
    received = got[0]
    assert isinstance(received, SampleBatch)
    assert [{k: type(v) for k, v in sample.items()} for sample in received.values] == [
        {"big": int, "small": int, "near": int},
        {"float": float, "int": int, "flag": bool, "off": bool, "text": str},
        {"tiny": float, "huge": float, "neg": float},
    ]
    assert str(received.values[2]["neg"]) == "-0.0"


async def test_each_twins_batches_arrive_in_publish_order(nodes: Nodes) -> None:
    """Two publishers (as two device sessions) of three twins at once: each twin's batches,
    of all its streams, reach the other node in the order they were published."""
    got: dict[int, list[int]] = {}

    def record(subject: str, message: object) -> None:
        assert isinstance(message, SampleBatch) and message.seq is not None
        got.setdefault(message.twin_id, []).append(message.seq)

    nodes.b.subscribe("samples.*", record)

    async def device(twin_id: int, count: int) -> None:
        for seq in range(count):
            stream = ("telemetry", "imu")[seq % 2]
            await nodes.a.publish(samples_subject(twin_id, stream), batch(twin_id, stream, [], seq))

    await asyncio.gather(device(1, 150), device(2, 150), device(3, 150))
    await nodes.b.caught_up()
    assert got == {1: list(range(150)), 2: list(range(150)), 3: list(range(150))}


async def test_publishes_in_flight_at_once_keep_their_order(nodes: Nodes) -> None:
    """Many publishes of one twin awaited together (the producer batches them in one
    request): the idempotent producer keeps their order."""
    got: list[int] = []
    nodes.b.subscribe("samples.4.t", lambda s, m: got.append(m))  # type: ignore[arg-type]
    await asyncio.gather(*(nodes.a.publish("samples.4.t", i) for i in range(500)))
    await nodes.b.caught_up()
    assert got == list(range(500))


async def test_samples_are_keyed_by_twin_on_the_samples_topic(
    nodes: Nodes, kafka: KafkaBroker
) -> None:
    for stream in ("telemetry", "imu", "fmu"):
        await nodes.a.publish(samples_subject(7, stream), batch(7, stream, [{"x": 1}]))
    await nodes.a.publish(samples_subject(8, "telemetry"), batch(8, "telemetry", [{"x": 2}]))
    await nodes.a.publish("commands.7", {"name": "pause"})
    topic = f"{nodes.prefix}.samples"
    consumer = AIOKafkaConsumer(bootstrap_servers=kafka.bootstrap, group_id=None)
    await consumer.start()
    try:
        partitions = [TopicPartition(topic, p) for p in range(4)]
        consumer.assign(partitions)
        await consumer.seek_to_beginning(*partitions)
        records = []
        while len(records) < 4:
            for chunk in (await consumer.getmany(timeout_ms=5000)).values():
                records.extend(chunk)
    finally:
        await consumer.stop()
    by_key: dict[bytes, set[int]] = {}
    for record in records:
        by_key.setdefault(record.key, set()).add(record.partition)
    assert set(by_key) == {b"7", b"8"}
    assert len(by_key[b"7"]) == 1  # all three streams of twin 7 in one partition


async def test_a_raising_subscriber_on_one_node_stops_nothing(
    nodes: Nodes, caplog: pytest.LogCaptureFixture
) -> None:
    seen: list[tuple[str, int]] = []

    def broken(subject: str, message: object) -> None:
        raise RuntimeError("subscriber bug")

    nodes.b.subscribe("samples.*", broken)
    nodes.b.subscribe("samples.*", lambda s, m: seen.append(("b", m)))  # type: ignore[arg-type]
    nodes.a.subscribe("samples.*", lambda s, m: seen.append(("a", m)))  # type: ignore[arg-type]
    with caplog.at_level(logging.ERROR, logger="twinlink.bus"):
        for i in range(3):
            await nodes.a.publish("samples.1.t", i)
        await nodes.a.caught_up()
        await nodes.b.caught_up()
    assert sorted(seen) == [("a", 0), ("a", 1), ("a", 2), ("b", 0), ("b", 1), ("b", 2)]
    failures = [r for r in caplog.records if r.getMessage() == "bus subscriber failed"]
    assert len(failures) == 3


async def test_a_batch_of_a_hundred_thousand_samples_goes_through(nodes: Nodes) -> None:
    got: list[object] = []
    nodes.b.subscribe("samples.9.big", lambda s, m: got.append(m))
    values: list[dict[str, Value]] = [
        {"angle": i * 0.001, "force": i, "ok": i % 2 == 0} for i in range(100_000)
    ]
    sent = batch(9, "big", values)
    await nodes.a.publish("samples.9.big", sent)
    await nodes.b.caught_up()
    assert got == [sent]


async def test_a_node_started_later_sees_what_is_published_after_its_start(
    nodes: Nodes, kafka: KafkaBroker
) -> None:
    await nodes.a.publish("samples.1.t", "before")
    late = KafkaBus(kafka.bootstrap, topic_prefix=nodes.prefix, partitions=4)
    got: list[object] = []
    late.subscribe("samples.*", lambda s, m: got.append(m))
    await late.start()
    try:
        await nodes.a.publish("samples.1.t", "after")
        await late.caught_up()
    finally:
        await late.stop()
    assert got == ["after"]


async def test_a_record_the_bus_cannot_read_is_logged_and_skipped(
    nodes: Nodes, kafka: KafkaBroker, caplog: pytest.LogCaptureFixture
) -> None:
    got: list[object] = []
    nodes.b.subscribe("samples.*", lambda s, m: got.append(m))
    producer = AIOKafkaProducer(bootstrap_servers=kafka.bootstrap)
    await producer.start()
    try:
        for junk in (b"\xc1 not msgpack", b"\x93\x09\xa1x\x00", b""):
            await producer.send_and_wait(f"{nodes.prefix}.samples", junk, key=b"1")
    finally:
        await producer.stop()
    with caplog.at_level(logging.WARNING, logger="twinlink.bus"):
        await nodes.a.publish("samples.1.t", "still read")
        await nodes.a.caught_up()
        await nodes.b.caught_up()
    assert got == ["still read"]
    skipped = [
        r for r in caplog.records if r.getMessage() == "skipped a record the bus cannot read"
    ]
    assert len(skipped) == 6  # three on each node
    assert all(r.topic == f"{nodes.prefix}.samples" for r in skipped)  # type: ignore[attr-defined]


async def test_a_message_kafka_cannot_carry_is_refused_before_sending(nodes: Nodes) -> None:
    got: list[object] = []
    nodes.b.subscribe("samples.*", lambda s, m: got.append(m))
    with pytest.raises(UnencodableMessageError, match=r"samples\.1\.t cannot be sent over Kafka"):
        await nodes.a.publish("samples.1.t", {"when": object()})
    with pytest.raises(UnencodableMessageError):
        await nodes.a.publish("samples.1.t", 2**64)  # past int64 and uint64
    await nodes.a.publish("samples.1.t", "next")
    await nodes.b.caught_up()
    assert got == ["next"]


async def test_no_broker_at_the_address_is_a_clear_error_and_leaves_nothing_running() -> None:
    bus = KafkaBus(f"127.0.0.1:{free_port()}", topic_prefix="nowhere")
    with pytest.raises(KafkaBusError, match=r"cannot use Kafka at 127\.0\.0\.1:") as caught:
        await bus.start()
    assert caught.value.status == 503
    assert "check that the brokers run" in str(caught.value)
    with pytest.raises(RuntimeError, match="before start"):
        await bus.publish("samples.1.t", 1)


async def test_a_live_watcher_on_one_node_gets_the_batches_published_on_the_other(
    nodes: Nodes,
) -> None:
    """The live hub on node B fed by the Kafka bus: a browser there follows a twin whose
    device sends to node A, every sample exact, in order."""
    hub = LiveHub(nodes.b)
    sub = Subscription("s1", 7, "rig", "telemetry")
    sub.started = True
    outbox = Outbox(64)
    hub.add(sub, outbox)
    try:
        for seq in range(3):
            values: list[dict[str, Value]] = [{"angle": seq + 0.5, "count": I64_MAX - seq}]
            await nodes.a.publish(samples_subject(7, "telemetry"), batch(7, "telemetry", values))
        await nodes.a.publish(samples_subject(7, "imu"), batch(7, "imu", [{"angle": 9.0}]))
        await nodes.b.caught_up()
    finally:
        hub.close()
    messages = []
    while (raw := outbox.take()) is not None:
        messages.append(orjson.loads(raw))
    assert [(m["sub"], m["stream"]) for m in messages] == [("s1", "telemetry")] * 3  # no imu
    assert [m["samples"][0]["values"] for m in messages] == [
        {"angle": seq + 0.5, "count": I64_MAX - seq} for seq in range(3)
    ]


async def test_the_reader_outlives_a_failed_fetch(
    nodes: Nodes, caplog: pytest.LogCaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(kafka_bus_module, "_RETRY_S", 0.01)
    consumer = nodes.b._consumer
    assert consumer is not None
    fetch = consumer.getmany
    failures: list[Exception] = [KafkaConnectionError("broker away"), RuntimeError("client bug")]

    async def flaky(*args: object, **kwargs: object) -> object:
        if failures:
            raise failures.pop(0)
        return await fetch(*args, **kwargs)

    got: list[object] = []
    nodes.b.subscribe("samples.*", lambda s, m: got.append(m))
    with caplog.at_level(logging.WARNING, logger="twinlink.bus"):
        monkeypatch.setattr(consumer, "getmany", flaky)
        async with asyncio.timeout(10):  # the reader's next fetches fail (its current one ends)
            while failures:
                await asyncio.sleep(0.01)
        await nodes.a.publish("samples.1.t", "after the failures")
        await nodes.b.caught_up()
    assert got == ["after the failures"]
    retried = "reading the Kafka bus failed; retrying"
    retries = [r for r in caplog.records if r.getMessage() == retried]
    assert [r.error for r in retries] == [  # type: ignore[attr-defined]
        "KafkaConnectionError('broker away')",
        "RuntimeError('client bug')",
    ]
    assert not retries[0].exc_info  # a Kafka error is a line; anything else its traceback
    assert retries[1].exc_info and isinstance(retries[1].exc_info[1], RuntimeError)


async def test_starting_a_started_bus_is_refused_and_it_keeps_working(nodes: Nodes) -> None:
    got: list[object] = []
    nodes.b.subscribe("samples.*", lambda s, m: got.append(m))
    with pytest.raises(RuntimeError, match="start twice"):
        await nodes.a.start()
    await nodes.a.publish("samples.1.t", "still")
    await nodes.b.caught_up()
    assert got == ["still"]


async def test_ready_while_started_and_reading_only(kafka: KafkaBroker) -> None:
    """What /readyz asks of the bus: a bus not started, or stopped, is not ready."""
    bus = KafkaBus(kafka.bootstrap, topic_prefix=f"r{secrets.token_hex(4)}", partitions=1)
    assert not await bus.ready()
    await bus.start()
    try:
        assert await bus.ready()
    finally:
        await bus.stop()
    assert not await bus.ready()
