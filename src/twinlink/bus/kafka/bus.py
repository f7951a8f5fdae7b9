"""The Kafka bus: what one node publishes, every node's subscribers get.

Publishing sends one record (topics.py says to which topic and partition, codec.py what it
holds) with an idempotent producer and acks=all, and returns once Kafka has it: written by
every in-sync replica, never twice when the producer retries. Each node reads every partition
of every bus topic itself, without a consumer group: a group would share the partitions out,
and each node would see only its share of the twins, but every node must see every sample (a
browser on node A follows a device connected to node B). A node reads from where the topics
ended when it started; like the memory bus, the bus holds no history for late subscribers.

Records are handed to the subscribers on the event loop by the same dispatch as the memory
bus's (`MemoryBus.publish_now`): exact subjects and `.*` prefixes, a handler that raises is
logged and stays subscribed.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from aiokafka import AIOKafkaConsumer, AIOKafkaProducer, TopicPartition
from aiokafka.admin import AIOKafkaAdminClient, NewTopic
from aiokafka.errors import KafkaError

from twinlink.bus.base import Handler, Unsubscribe
from twinlink.bus.kafka.codec import UndecodableRecordError, decode, encode
from twinlink.bus.kafka.topics import key_of, topic_names, topic_of
from twinlink.bus.memory import MemoryBus
from twinlink.domain.errors import UnavailableError

log = logging.getLogger("twinlink.bus")

# A batch may hold up to 100 000 samples (domain/samples.py): a few MB, past Kafka's 1 MB
# default for one record. The topics are created allowing this much, and the clients use it.
MAX_RECORD_BYTES = 32 * 1024 * 1024
_TOPIC_EXISTS = 36  # Kafka's TOPIC_ALREADY_EXISTS error code
_RETRY_S = 1.0
_TOPICS_WAIT_S = 30.0


class KafkaBusError(UnavailableError):
    """Kafka could not be reached, or did not take a message (503, Retry-After)."""


class KafkaBus:
    def __init__(
        self,
        bootstrap_servers: str,
        *,
        topic_prefix: str = "twinlink",
        partitions: int = 8,
        replication_factor: int = 1,
        client_id: str = "twinlink",
        linger_ms: int = 1,
        publish_timeout_s: float = 5.0,
    ) -> None:
        """`bootstrap_servers` is "host:port[,host:port...]". `partitions` and
        `replication_factor` apply to the topics this bus creates when they do not exist
        yet (a cluster of three brokers wants 3 and min.insync.replicas=2). `linger_ms`
        is how long the producer waits to put concurrent publishes in one request.
        `publish_timeout_s` bounds how long `publish` waits for Kafka (the producer alone
        would wait up to its 40 s request timeout while the brokers are away)."""
        self.bootstrap_servers = bootstrap_servers
        self.topic_prefix = topic_prefix
        self.topics = topic_names(topic_prefix)
        self._partitions = partitions
        self._replication = replication_factor
        self._client_id = client_id
        self._linger_ms = linger_ms
        self.publish_timeout_s = publish_timeout_s
        self._local = MemoryBus()  # this node's subscriptions and their dispatch
        self._producer: AIOKafkaProducer | None = None
        self._consumer: AIOKafkaConsumer | None = None
        self._reader: asyncio.Task[None] | None = None

    async def start(self) -> None:
        if self._reader is not None:
            raise RuntimeError("KafkaBus.start twice: stop() it first")
        try:
            partitions = await self._prepare_topics()
            self._producer = await self._started(self._new_producer())
            self._consumer = await self._started(self._new_consumer())
            await self._read_from_the_end(self._consumer, partitions)
        except BaseException as err:
            await self.stop()  # nothing of a failed start is left running
            if not isinstance(err, KafkaError):
                raise
            raise KafkaBusError(
                f"cannot use Kafka at {self.bootstrap_servers}: {err!r}; check that the "
                "brokers run and that this address reaches them"
            ) from err
        self._reader = asyncio.create_task(self._read(self._consumer), name="kafka-bus-reader")

    async def stop(self) -> None:
        if self._reader is not None:
            self._reader.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._reader
            self._reader = None
        for client in (self._consumer, self._producer):  # the producer sends what it holds
            if client is not None:
                await client.stop()
        self._consumer = self._producer = None
        await self._local.stop()

    async def ready(self) -> bool:
        """Started, reading, and a broker of the cluster takes a connection (the producer's
        client opens one to a broker it knows when it has none; what /readyz asks)."""
        if self._producer is None or self._reader is None or self._reader.done():
            return False
        client = self._producer.client
        node = client.get_random_node()
        return node is not None and bool(await client.ready(node))

    async def publish(self, subject: str, message: object) -> None:
        """Returns once Kafka has the message (acks=all); raises KafkaBusError if it does
        not take it, after the producer's own retries, or has not within
        `publish_timeout_s`. A message given up on that way may still be in the producer's
        buffer and reach Kafka later: whoever sends it again after the error makes it a
        duplicate on the bus, never a message lost (docs/decisions/0013)."""
        if self._producer is None:
            raise RuntimeError("KafkaBus.publish before start()")
        record = encode(subject, message)
        try:
            async with asyncio.timeout(self.publish_timeout_s):
                await self._producer.send_and_wait(
                    topic_of(subject, self.topic_prefix), record, key=key_of(subject)
                )
        except TimeoutError as err:
            raise KafkaBusError(
                f"Kafka at {self.bootstrap_servers} did not take the message for {subject} "
                f"within {self.publish_timeout_s:g} s (TWINLINK_BUS_PUBLISH_TIMEOUT_S): it may "
                "be restarting or unreachable; send it again later"
            ) from err
        except KafkaError as err:
            raise KafkaBusError(
                f"Kafka at {self.bootstrap_servers} did not take the message for {subject}: {err!r}"
            ) from err

    def subscribe(self, pattern: str, handler: Handler) -> Unsubscribe:
        return self._local.subscribe(pattern, handler)

    async def caught_up(self, timeout_s: float = 30.0) -> None:
        """Returns once this node has handed its subscribers every record that Kafka held when
        called, whichever node published it (TimeoutError after `timeout_s`)."""
        consumer = self._consumer
        if consumer is None:
            raise RuntimeError("KafkaBus.caught_up before start()")
        ends: dict[TopicPartition, int] = await consumer.end_offsets(list(consumer.assignment()))
        async with asyncio.timeout(timeout_s):
            for partition, end in ends.items():
                # The position moves as the reader takes records, and the reader hands each
                # to the subscribers before it next awaits.
                while await consumer.position(partition) < end:
                    await asyncio.sleep(0.005)

    # -- the clients -------------------------------------------------------------------------

    def _new_producer(self) -> AIOKafkaProducer:
        return AIOKafkaProducer(
            bootstrap_servers=self.bootstrap_servers,
            client_id=self._client_id,
            acks="all",
            enable_idempotence=True,
            linger_ms=self._linger_ms,
            max_request_size=MAX_RECORD_BYTES,
        )

    def _new_consumer(self) -> AIOKafkaConsumer:
        return AIOKafkaConsumer(
            bootstrap_servers=self.bootstrap_servers,
            client_id=self._client_id,
            group_id=None,  # no group: this node reads every partition (see the docstring)
            enable_auto_commit=False,
            max_partition_fetch_bytes=MAX_RECORD_BYTES,
            fetch_max_wait_ms=100,
        )

    @staticmethod
    async def _started(client: Any) -> Any:
        try:
            await client.start()
        except BaseException:
            await client.stop()  # a client that failed to start still holds its connections
            raise
        return client

    async def _prepare_topics(self) -> list[TopicPartition]:
        """Create the bus's topics that do not exist yet; returns all their partitions."""
        admin = AIOKafkaAdminClient(
            bootstrap_servers=self.bootstrap_servers, client_id=self._client_id
        )
        await admin.start()
        try:
            await self._create_topics(admin)
            return await self._partitions_of_topics(admin)
        finally:
            await admin.close()

    async def _create_topics(self, admin: AIOKafkaAdminClient) -> None:
        config = {"max.message.bytes": str(MAX_RECORD_BYTES)}
        size = (self._partitions, self._replication)
        wanted = [NewTopic(topic, *size, None, config) for topic in self.topics]
        response = await admin.create_topics(wanted)
        for topic, code, *message in response.topic_errors:
            if code not in (0, _TOPIC_EXISTS):
                detail = message[0] if message and message[0] else f"error code {code}"
                raise KafkaBusError(f"Kafka refused to create the topic {topic}: {detail}")

    async def _partitions_of_topics(self, admin: AIOKafkaAdminClient) -> list[TopicPartition]:
        # Topics just created have no leader for a moment: wait until each partition has one.
        deadline = asyncio.get_running_loop().time() + _TOPICS_WAIT_S
        while True:
            found = _led_partitions(await admin.describe_topics(self.topics))
            missing = [topic for topic in self.topics if not found.get(topic)]
            if not missing:
                return [TopicPartition(t, p) for t in self.topics for p in sorted(found[t])]
            if asyncio.get_running_loop().time() > deadline:
                raise KafkaBusError(
                    f"Kafka at {self.bootstrap_servers} has no leader for partitions of "
                    f"{missing} {_TOPICS_WAIT_S:.0f} s after they were created"
                )
            await asyncio.sleep(0.1)

    async def _read_from_the_end(
        self, consumer: AIOKafkaConsumer, partitions: list[TopicPartition]
    ) -> None:
        """Assign every partition of the bus's topics and fix each position at its end now,
        so that whatever is published after start() returns is read (a lazy seek would skip
        what is published before the first fetch)."""
        consumer.assign(partitions)
        await consumer.seek_to_end(*partitions)
        for partition in partitions:
            await consumer.position(partition)

    # -- reading -----------------------------------------------------------------------------

    async def _read(self, consumer: AIOKafkaConsumer) -> None:
        while True:
            try:
                fetched = await consumer.getmany(timeout_ms=1000)
            except Exception as err:  # the reader outlives any one failure, or the node is deaf
                log.warning(
                    "reading the Kafka bus failed; retrying",
                    extra={"event": "bus_read_failed", "error": repr(err)},
                    exc_info=not isinstance(err, KafkaError),  # anything else is a bug
                )
                await asyncio.sleep(_RETRY_S)
                continue
            for records in fetched.values():
                for record in records:
                    self._deliver(record.value, record.topic)

    def _deliver(self, value: bytes | None, topic: str) -> None:
        try:
            subject, message = decode(value or b"")
        except UndecodableRecordError as err:
            log.warning(
                "skipped a record the bus cannot read",
                extra={"event": "bus_bad_record", "topic": topic, "error": str(err)},
            )
            return
        self._local.publish_now(subject, message)


def _led_partitions(topics: list[dict[str, Any]]) -> dict[str, list[int]]:
    """Metadata's topics -> the partitions of each that have a leader (all or none: a topic
    with a partition still without one counts as not ready)."""
    ready: dict[str, list[int]] = {}
    for topic in topics:
        partitions = topic.get("partitions") or []
        if (
            topic.get("error_code") == 0
            and partitions
            and all(p.get("error_code") == 0 and p.get("leader", -1) >= 0 for p in partitions)
        ):
            ready[topic["topic"]] = [p["partition"] for p in partitions]
    return ready
