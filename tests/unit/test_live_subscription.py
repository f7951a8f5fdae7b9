"""A live subscription: the signal filter, max_rate decimation by sample time, the message."""

from __future__ import annotations

from itertools import pairwise
from typing import Any

import orjson

from twinlink.domain.samples import SampleBatch, Value
from twinlink.live.subscription import Subscription

T0 = 1_732_200_000_000_000_000
MS = 1_000_000


def make_batch(times: list[int], values: list[dict[str, Value]]) -> SampleBatch:
    return SampleBatch(1, "rig", "telemetry", times, values, received_ns=T0 + 10**9)


def sub(**kwargs: Any) -> Subscription:
    return Subscription("a", 1, "rig", "telemetry", **kwargs)


def test_without_filter_or_rate_everything_is_sent_as_one_message() -> None:
    batch = make_batch([T0, T0 + MS], [{"x": 1.5, "y": 2}, {"x": 2.5}])
    message = orjson.loads(sub().message(batch, sent_ns=T0 + 2 * 10**9) or b"")
    assert message == {
        "type": "samples",
        "sub": "a",
        "twin": "rig",
        "stream": "telemetry",
        "received": T0 + 10**9,
        "sent": T0 + 2 * 10**9,
        "samples": [
            {"time": T0, "values": {"x": 1.5, "y": 2}},
            {"time": T0 + MS, "values": {"x": 2.5}},
        ],
    }


def test_the_filter_keeps_only_the_named_signals_and_skips_samples_without_any() -> None:
    batch = make_batch(
        [T0, T0 + MS, T0 + 2 * MS], [{"x": 1, "y": 2, "z": 3}, {"z": 4}, {"y": 5, "s": "on"}]
    )
    selected = sub(signals=frozenset({"x", "y", "missing"})).select(batch)
    assert selected == [
        {"time": T0, "values": {"x": 1, "y": 2}},
        {"time": T0 + 2 * MS, "values": {"y": 5}},
    ]


def test_a_batch_with_nothing_selected_makes_no_message() -> None:
    batch = make_batch([T0], [{"z": 1}])
    assert sub(signals=frozenset({"x"})).message(batch, T0) is None


def test_max_rate_keeps_a_sample_when_one_interval_passed_since_the_last_kept() -> None:
    s = sub(max_rate=100)  # at most one sample per 10 ms of sample time
    times = [T0 + i * MS for i in range(35)]  # 1 kHz for 35 ms
    kept = [x["time"] for x in s.select(make_batch(times, [{"x": i} for i in range(35)]))]
    assert kept == [T0, T0 + 10 * MS, T0 + 20 * MS, T0 + 30 * MS]


def test_max_rate_carries_over_from_batch_to_batch() -> None:
    s = sub(max_rate=100)
    first = s.select(make_batch([T0, T0 + 4 * MS], [{"x": 1}, {"x": 2}]))
    second = s.select(make_batch([T0 + 8 * MS, T0 + 12 * MS], [{"x": 3}, {"x": 4}]))
    assert [x["values"]["x"] for x in first + second] == [1, 4]


def test_max_rate_with_uneven_times_never_exceeds_the_rate() -> None:
    s = sub(max_rate=50)  # 20 ms
    offsets = [0, 3, 19, 21, 22, 40, 41, 60, 79, 80, 100]
    batch = make_batch([T0 + o * MS for o in offsets], [{"x": o} for o in offsets])
    kept = [x["values"]["x"] for x in s.select(batch)]
    assert kept == [0, 21, 41, 79, 100]
    assert all(b - a >= 20 for a, b in pairwise(kept))


def test_a_clock_that_goes_back_starts_the_decimation_again() -> None:
    s = sub(max_rate=1)
    batch = make_batch(
        [T0, T0 + 100 * MS, T0 - 10**9, T0 - 10**9 + MS], [{"x": i} for i in range(4)]
    )
    assert [x["values"]["x"] for x in s.select(batch)] == [0, 2]


def test_decimation_counts_only_samples_that_pass_the_filter() -> None:
    s = sub(signals=frozenset({"x"}), max_rate=100)
    batch = make_batch(
        [T0, T0 + 10 * MS, T0 + 11 * MS], [{"y": 1}, {"y": 2}, {"x": 3}]
    )  # the first x is at +11 ms: it is kept, the y samples did not start the count
    assert s.select(batch) == [{"time": T0 + 11 * MS, "values": {"x": 3}}]
