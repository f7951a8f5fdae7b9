"""A real Apache Kafka broker for the tests: one KRaft node (broker and controller in one JVM,
no ZooKeeper), run from the Maven Central jars that scripts/ensure-kafka.sh keeps in
.cache/kafka/<version>/libs, on free loopback ports in a temporary folder. Starting and
stopping it is twinlink.devcluster.kafka's (the local cluster's broker too); `start_kafka`
and `restart_kafka` (same folder, data and ports) are re-exported here.

One broker serves the whole session, started by the first test that asks for the `kafka`
fixture. A test module imports the fixture (`from tests.integration._kafka import kafka`);
pytest then holds one fixture per module, so the broker itself is kept here, started once
and stopped when the session's last such fixture ends. Being session-scoped, the fixture is
set up before a module's own fixtures, so the leak check (tests/_hygiene.py) does not count
the JVM against the module or the test that first asked for it.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import ROOT
from twinlink.devcluster import kafka as devcluster_kafka
from twinlink.devcluster.kafka import KafkaBroker, restart_kafka, start_kafka, stop_kafka

__all__ = ["KafkaBroker", "kafka", "kafka_libs", "restart_kafka", "start_kafka", "stop_kafka"]


def kafka_libs() -> Path:
    """The folder of the broker's jars, fetched first if need be; the test fails saying why
    when they cannot be had."""
    try:
        return devcluster_kafka.kafka_libs(ROOT)
    except devcluster_kafka.KafkaError as err:
        pytest.fail(str(err), pytrace=False)


_broker: KafkaBroker | None = None
_users = 0


@pytest.fixture(scope="session")
def kafka(tmp_path_factory: pytest.TempPathFactory) -> Iterator[KafkaBroker]:
    """The session's Kafka broker (started by the first module that asks)."""
    global _broker, _users
    if _broker is None or _broker.process.poll() is not None:
        _broker = start_kafka(tmp_path_factory.mktemp("kafka"), kafka_libs())
    _users += 1
    try:
        yield _broker
    finally:
        _users -= 1
        if _users == 0:
            stop_kafka(_broker)
            _broker = None
