"""A processor's catch-up on a shared store (processors/catchup.py): what it replays from
history after its saved position, the held live batches handed over without what the replay
had, its bounds, and a history that cannot be read. History here is a list of rows read by the
same calls the PostgreSQL store answers; the whole path runs on two real nodes in
tests/integration/test_scale_out_leases.py."""

from __future__ import annotations

from typing import Any

import pytest

from twinlink.domain.errors import NotFoundError, StorageError
from twinlink.domain.history import SamplePage
from twinlink.domain.samples import SampleBatch
from twinlink.processors import catchup
from twinlink.processors.catchup import CatchUp
from twinlink.processors.supervisor import EventTuple
from twinlink.store.leases import Claims, LocalLeases, Position, new_holder


class History:
    """Stored rows of one stream, read as HistoryReadStore reads them (pages, a cursor)."""

    def __init__(self, rows: list[tuple[int, dict[str, Any]]], fail: bool = False) -> None:
        self.rows = [{"time": t, "values": v} for t, v in rows]
        self.fail = fail

    async def extent(self, twin_id: int, stream: str, signals: Any) -> tuple[int, int] | None:
        if not self.rows:
            raise NotFoundError(f"no stream {stream!r}")
        return self.rows[0]["time"], self.rows[-1]["time"]

    async def samples(
        self, twin_id: int, stream: str, signals: Any, start: int, end: int, limit: int,
        after: tuple[int, int] | None = None,
    ) -> SamplePage:  # fmt: skip
        if self.fail:
            raise StorageError("the database cannot be reached")
        first = after[1] if after else 0
        todo = [(i, r) for i, r in enumerate(self.rows) if start <= r["time"] <= end][first:]
        page = todo[:limit]
        more = (page[-1][1]["time"], first + limit) if len(todo) > limit else None
        return SamplePage([r for _, r in page], more)


def batch(*samples: tuple[int, float]) -> SampleBatch:
    return SampleBatch(1, "rig", "in", [t for t, _ in samples],
                       [{"x": x} for _, x in samples], 0)  # fmt: skip


class Fed:
    """What the processor was given, in order, and the events recorded."""

    def __init__(self) -> None:
        self.samples: list[tuple[int, float]] = []
        self.replayed: list[tuple[int, float]] = []
        self.events: list[EventTuple] = []

    def feed(self, b: SampleBatch) -> None:
        self.samples += [(t, v["x"]) for t, v in zip(b.times, b.values, strict=True)]

    async def replay(self, b: SampleBatch) -> None:
        self.feed(b)
        self.replayed += [(t, v["x"]) for t, v in zip(b.times, b.values, strict=True)]

    def on_events(self, events: list[EventTuple]) -> None:
        self.events += events


async def make(history: History, position: Position | None) -> tuple[CatchUp, Fed]:
    claims = Claims(LocalLeases(), "processor", new_holder())
    assert await claims.claim(7)
    if position is not None:
        assert await claims.save_positions({7: position})
    fed = Fed()
    return CatchUp(7, 1, "in", claims, history, fed.feed, fed.replay, fed.on_events), fed  # type: ignore[arg-type]


def stored(*times: int) -> list[tuple[int, dict[str, Any]]]:
    return [(t, {"x": float(t)}) for t in times]


async def test_a_new_processor_starts_from_the_newest_stored_time_and_replays_nothing() -> None:
    up, fed = await make(History(stored(1, 2, 3)), None)
    assert up.take(batch((4, 4.0))) is None  # held until the catch-up is done
    await up.run()
    assert up.start == Position("in", 3)
    assert await up.claims.position(7) == Position("in", 3)  # saved at once
    assert fed.samples == [(4, 4.0)] and fed.replayed == [] and fed.events == []
    assert up.live and up.take(batch((5, 5.0))) is not None


async def test_an_empty_stream_starts_from_before_any_sample() -> None:
    up, fed = await make(History([]), None)
    await up.run()
    assert up.start is not None and up.start.t < 0
    assert fed.samples == []


async def test_what_came_after_the_position_is_replayed_and_the_live_batches_not_again() -> None:
    up, fed = await make(History(stored(1, 2, 3, 4, 5, 6)), Position("in", 3))
    # Held while catching up: 5 and 6 were stored and published (in the replay too), 7 not.
    assert up.take(batch((5, 5.0), (6, 6.0), (7, 7.0))) is None
    await up.run()
    assert fed.replayed == [(4, 4.0), (5, 5.0), (6, 6.0)]
    assert fed.samples == [(4, 4.0), (5, 5.0), (6, 6.0), (7, 7.0)]  # each once, in order
    [event] = fed.events
    assert event[0] == "caught_up" and event[3]["replayed"] == 3 and event[3]["skipped"] == 0
    # A batch the replay had that reaches this node over the bus only now: left out too.
    assert up.take(batch((4, 4.0))) is None
    late = up.take(batch((4, 40.0), (8, 8.0)))  # alike in time only: not the same sample
    assert late is not None and late.times == [4, 8] and late.values == [{"x": 40.0}, {"x": 8.0}]


async def test_the_tail_ends(monkeypatch: pytest.MonkeyPatch) -> None:
    up, fed = await make(History(stored(1, 2)), Position("in", 1))
    await up.run()
    assert fed.replayed == [(2, 2.0)]
    monkeypatch.setattr(catchup, "TAIL_S", -1.0)
    up._go_live()  # the tail ends at once now
    assert up.take(batch((2, 2.0))) is not None  # no longer checked against the replay


async def test_another_stream_s_position_is_not_this_one_s() -> None:
    up, fed = await make(History(stored(1, 2, 3)), Position("old", 1))
    await up.run()
    assert up.start == Position("in", 3) and fed.replayed == []


async def test_a_long_catch_up_keeps_the_newest_samples_and_says_what_it_skipped(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(catchup, "MAX_REPLAY", 3)
    monkeypatch.setattr(catchup, "PAGE", 2)
    up, fed = await make(History(stored(*range(1, 11))), Position("in", 2))
    await up.run()
    assert fed.replayed == [(8, 8.0), (9, 9.0), (10, 10.0)]
    cut, done = fed.events
    assert cut[0] == "catch_up_cut" and "5 samples skipped" in cut[1]
    assert done[0] == "caught_up" and done[3]["skipped"] == 5


async def test_nothing_older_than_the_age_bound_is_replayed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(catchup, "MAX_AGE_NS", 3)
    up, fed = await make(History(stored(*range(1, 11))), Position("in", 2))
    await up.run()
    assert fed.replayed == [(8, 8.0), (9, 9.0), (10, 10.0)]  # those after 10 - 3
    assert [e[0] for e in fed.events] == ["catch_up_cut", "caught_up"]


async def test_a_history_that_cannot_be_read_is_an_event_and_the_processor_goes_on_live() -> None:
    up, fed = await make(History(stored(1, 2, 3), fail=True), Position("in", 1))
    assert up.take(batch((4, 4.0))) is None
    await up.run()
    assert fed.samples == [(4, 4.0)]
    [event] = fed.events
    assert event[0] == "catch_up_failed" and "cannot be reached" in event[1]


async def test_live_batches_held_past_the_bound_drop_the_oldest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(catchup, "MAX_REPLAY", 3)
    up, fed = await make(History(stored(1)), None)
    for t in (10, 20, 30):
        assert up.take(batch((t, 0.0), (t + 1, 0.0))) is None
    await up.run()
    assert [t for t, _ in fed.samples] == [30, 31]  # as a worker's full queue drops them
    assert up.dropped == 4
