"""The Kafka bus on a real broker (tests/integration/_kafka.py): the broker the tests start,
and two KafkaBus instances on it as two nodes of a cluster would be."""

from __future__ import annotations

import pytest
from aiokafka import AIOKafkaConsumer, AIOKafkaProducer, TopicPartition

from tests.integration._kafka import KafkaBroker, kafka

pytestmark = pytest.mark.integration
__all__ = ["kafka"]


async def test_the_tests_broker_takes_and_gives_back_a_record(kafka: KafkaBroker) -> None:
    producer = AIOKafkaProducer(bootstrap_servers=kafka.bootstrap, acks="all")
    await producer.start()
    try:
        sent = await producer.send_and_wait("broker-check", b"hello", key=b"k")
    finally:
        await producer.stop()
    consumer = AIOKafkaConsumer(bootstrap_servers=kafka.bootstrap, group_id=None)
    await consumer.start()
    try:
        tp = TopicPartition("broker-check", sent.partition)
        consumer.assign([tp])
        consumer.seek(tp, sent.offset)
        record = await consumer.getone()
    finally:
        await consumer.stop()
    assert (record.key, record.value) == (b"k", b"hello")
