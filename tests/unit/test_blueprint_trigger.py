"""The alarm trigger: hysteresis sequences with exact event times, the minimum duration, rate
mode, commands, and a plain sample-by-sample loop as reference for random data and splits."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from twinlink.processors.blueprint import Batch, Context
from twinlink.processors.blueprints.trigger import Trigger, TriggerParams

T0 = 1_700_000_000_000_000_000
TENTH = 100_000_000  # 0.1 s in ns


def ctx(tmp_path: Path) -> Context:
    return Context(processor="p", twin="t", files=tmp_path, workdir=tmp_path)


def at(*indexes: int) -> list[int]:
    return [T0 + i * TENTH for i in indexes]


def feed(bp: Trigger, values: list[float], splits: tuple[int, ...] = ()) -> Batch:
    times = at(*range(len(values)))
    cuts = [0, *splits, len(values)]
    outs = [bp.process(Batch.of(times[a:b], x=values[a:b])) for a, b in pairwise(cuts)]
    return Batch.concat([o for o in outs if o is not None])


def events(c: Context) -> list[tuple[str, int]]:
    return [(e.kind, e.time_ns) for e in c.events]


def test_threshold_with_hysteresis(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    bp = Trigger(TriggerParams(signal="x", high=10, clear_at=8), c)
    assert bp.inputs() == ["x"] and bp.outputs() == ["x.alarm"]
    values = [5, 9, 11, 12, 9, 8.5, 7.9, 9, 10, 10.5, 7]
    out = feed(bp, values, splits=(3, 4, 9))
    assert out["x.alarm"].tolist() == [0, 0, 1, 1, 1, 1, 0, 0, 0, 1, 0]
    assert events(c) == [
        ("alarm", at(2)[0]),
        ("alarm_cleared", at(6)[0]),
        ("alarm", at(9)[0]),
        ("alarm_cleared", at(10)[0]),
    ]
    first = c.events[0]
    assert first.data == {"signal": "x", "value": 11.0}
    assert first.message == "x is 11, above 10"
    assert c.events[1].message == "x is 7.9, back below 8"


def test_below_with_the_raise_level_as_clear_level(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    bp = Trigger(TriggerParams(signal="x", direction="below", low=2), c)
    out = feed(bp, [3, 2, 1.9, 2, 2.1, 1])
    assert out["x.alarm"].tolist() == [0, 0, 1, 1, 0, 1]
    assert events(c) == [("alarm", at(2)[0]), ("alarm_cleared", at(4)[0]), ("alarm", at(5)[0])]
    assert c.events[0].message == "x is 1.9, below 2"


def test_minimum_duration_across_batches(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    bp = Trigger(TriggerParams(signal="x", high=10, min_duration_s=0.25), c)
    values = [11, 11, 11, 11, 5, 11, 11, 5, 11, 11, 10.5, 10.2]
    out = feed(bp, values, splits=(2, 9))
    assert out["x.alarm"].tolist() == [0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1]
    assert events(c) == [("alarm", at(3)[0]), ("alarm_cleared", at(4)[0]), ("alarm", at(11)[0])]
    assert c.events[0].message == "x is 11, above 10 for 0.25 s"


def test_rate_mode(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    p = TriggerParams(signal="x", mode="rate", rate_limit=5, clear_fraction=0.5)
    values = [0, 0.1, 0.2, 1.0, 1.3, 1.4, 0.6, 0.6]  # rates: -, 1, 1, 8, 3, 1, -8, 0
    out = feed(Trigger(p, c), values, splits=(3,))
    assert out["x.alarm"].tolist() == [0, 0, 0, 1, 1, 0, 1, 0]
    assert events(c) == [
        ("alarm", at(3)[0]),
        ("alarm_cleared", at(5)[0]),
        ("alarm", at(6)[0]),
        ("alarm_cleared", at(7)[0]),
    ]
    assert c.events[0].data["rate"] == pytest.approx(8.0)
    assert c.events[0].message == "x changes at 8/s, faster than 5/s"
    assert c.events[1].message == "x changes at 1/s, below 2.5/s"


def test_commands_on_raise_and_clear(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    p = TriggerParams(
        signal="x",
        high=1,
        command={"name": "stop", "params": {"speed": 0, "why": "x"}, "device": "crane"},
        clear_command={"name": "resume"},
    )
    feed(Trigger(p, c), [0, 2, 3, 0, 2])
    got = [(k.name, k.device, k.params) for k in c.commands]
    stop = ("stop", "crane", {"speed": 0, "why": "x"})
    assert got == [stop, ("resume", None, {}), stop]


def test_output_only_changes_and_missing_values(tmp_path: Path) -> None:
    bp = Trigger(TriggerParams(signal="x", high=1, output="changes"), ctx(tmp_path))
    nan = np.nan
    out = feed(bp, [0, nan, 0, 2, 2, nan, 0, 0], splits=(1, 5))
    assert out.times.tolist() == at(0, 3, 6) and out["x.alarm"].tolist() == [0, 1, 0]
    assert bp.process(Batch.of(at(9), other=[5.0])) is None
    assert bp.process(Batch.of(at(10), x=[0.0])) is None  # no change, nothing to say
    every = Trigger(TriggerParams(signal="x", high=1), ctx(tmp_path))
    out = feed(every, [0, nan, 2])
    assert out.times.tolist() == at(0, 2) and out["x.alarm"].tolist() == [0, 1]


def test_reconfigure_keeps_the_alarm_raised(tmp_path: Path) -> None:
    c = ctx(tmp_path)
    p = TriggerParams(signal="x", high=10)
    bp = Trigger(p, c)
    bp.process(Batch.of(at(0), x=[12.0]))
    assert bp.reconfigure(p.model_copy(update={"high": 11.0, "clear_at": 8.0})) is True
    out = bp.process(Batch.of(at(1, 2), x=[9.0, 7.0]))
    assert out is not None and out["x.alarm"].tolist() == [1, 0]
    assert events(c) == [("alarm", at(0)[0]), ("alarm_cleared", at(2)[0])]


def reference(times: np.ndarray, values: np.ndarray, p: TriggerParams) -> tuple[list, list]:
    """The trigger, one sample at a time."""
    raised, since, prev = False, None, None
    found, states = [], []
    for t, v in zip(times.tolist(), values.tolist(), strict=True):
        if p.mode == "threshold":
            on, off = (v > p.high, v < p.clear_level)
        else:
            rate = abs((v - prev[1]) / ((t - prev[0]) / 1e9)) if prev else np.nan
            prev = (t, v)
            on, off = rate > p.rate_limit, rate < p.rate_limit * p.clear_fraction
        since = (t if since is None else since) if on else None
        if on and not raised and t - since >= p.min_duration_s * 1e9:
            raised = True
            found.append(("alarm", t))
        elif off and raised:
            raised = False
            found.append(("alarm_cleared", t))
        states.append(float(raised))
    return found, states


@pytest.mark.parametrize(
    "params",
    [
        {"high": 1.0, "clear_at": -1.0, "min_duration_s": 0.3},
        {"high": 0.5},
        {"mode": "rate", "rate_limit": 6.0, "clear_fraction": 0.6, "min_duration_s": 0.1},
    ],
)
def test_random_walks_in_random_batches_match_the_loop(
    tmp_path: Path, params: dict[str, Any]
) -> None:
    rng = np.random.default_rng(11)
    n = 3000
    times = T0 + np.cumsum(rng.integers(1, 3, n)) * TENTH // 2
    values = np.cumsum(rng.normal(0, 0.5, n))
    values -= np.linspace(0, values[-1], n)
    p = TriggerParams(signal="x", **params)
    want_events, want_states = reference(times, values, p)
    assert len(want_events) > 10
    c = ctx(tmp_path)
    bp = Trigger(p, c)
    cuts = [0, *sorted(rng.choice(np.arange(1, n), 60, replace=False).tolist()), n]
    outs = [bp.process(Batch.of(times[a:b], x=values[a:b])) for a, b in pairwise(cuts)]
    got = Batch.concat([o for o in outs if o is not None])
    assert events(c) == want_events
    assert got["x.alarm"].tolist() == want_states


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ({}, "needs high"),
        ({"direction": "below", "high": 3}, "needs low"),
        ({"high": 3, "clear_at": 4}, "must not be above high"),
        ({"direction": "below", "low": 3, "clear_at": 2}, "must not be below low"),
        ({"mode": "rate"}, "rate_limit"),
        ({"mode": "rate", "rate_limit": 0}, "rate_limit"),
        ({"mode": "rate", "rate_limit": 1, "clear_fraction": 0}, "clear_fraction"),
        ({"high": 1, "min_duration_s": -1}, "min_duration_s"),
        ({"high": 1, "command": {"name": "a", "params": {"device": 1}}}, "may not be called"),
        ({"high": 1, "command": {"params": {}}}, "name"),
        ({"high": 1, "direction": "up"}, "direction"),
        ({"high": 1, "hysteresis": 1}, "hysteresis"),
    ],
)
def test_bad_params(values: dict[str, Any], match: str) -> None:
    with pytest.raises(ValidationError, match=match):
        TriggerParams(signal="x", **values)
