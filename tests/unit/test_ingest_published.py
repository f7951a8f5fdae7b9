"""A device's batch is acknowledged once it is stored AND on the bus (docs/decisions/0013):
what a failed publish after the commit leaves, and what the device's resend does then. The
tests here hold for every backend (tests/integration/test_postgres_ingest_published.py runs
them on PostgreSQL, with that backend's own ones)."""

from __future__ import annotations

from typing import Any

import pytest

from tests.unit._history import T
from tests.unit._history import history as history
from twinlink.domain.errors import UnavailableError
from twinlink.domain.records import Device
from twinlink.ingest.service import IngestService
from twinlink.store.history import HistoryStore

DEVICE = Device(
    id=3, twin_id=7, twin_slug="rig", name="sensor", description="", prefix="tld_x",
    created_ns=T, last_seen_ns=None,
)  # fmt: skip


class Parts:
    async def get_parts(self, twin_id: int) -> None:
        return None  # no interface: every signal is taken as it comes


class Registry:
    generation = 0
    store = Parts()


class FlakyBus:
    """A bus that refuses (as Kafka away does) while `down`, and keeps what it takes."""

    def __init__(self) -> None:
        self.down = False
        self.published: list[tuple[str, Any]] = []

    async def publish(self, subject: str, message: object) -> None:
        if self.down:
            raise UnavailableError("the bus is away; send it again")
        self.published.append((subject, message))


def body(seq: int) -> dict[str, Any]:
    return {"seq": seq, "time_unit": "ns", "samples": [{"time": T + seq, "values": {"x": seq}}]}


def seqs(bus: FlakyBus) -> list[int | None]:
    return [batch.seq for _, batch in bus.published]


@pytest.fixture
def bus() -> FlakyBus:
    return FlakyBus()


@pytest.fixture
def ingest(history: HistoryStore, bus: FlakyBus) -> IngestService:
    return IngestService(Registry(), history, bus)  # type: ignore[arg-type]


async def test_a_batch_is_published_once_and_its_resend_is_a_duplicate_not_published(
    ingest: IngestService, bus: FlakyBus
) -> None:
    first = await ingest.ingest(DEVICE, body(1))
    again = await ingest.ingest(DEVICE, body(1))  # the ack was lost: the device sends it again
    assert (first.accepted, first.duplicate) == (1, False)
    assert (again.accepted, again.duplicate) == (0, True)
    assert seqs(bus) == [1]


async def test_a_batch_the_bus_refused_is_not_acknowledged(
    ingest: IngestService, bus: FlakyBus
) -> None:
    bus.down = True
    with pytest.raises(UnavailableError):
        await ingest.ingest(DEVICE, body(1))
    assert bus.published == []
    bus.down = False
    await ingest.ingest(DEVICE, body(2))  # the next batch goes through as ever
    assert seqs(bus) == [2]
