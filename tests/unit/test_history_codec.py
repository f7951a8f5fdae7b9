"""History blocks (store/sqlite/history/codec.py): kinds, one column per signal, round trips
and summaries; and blocks of fewer than SMALL_BLOCK samples packed without numpy: the same
bytes and numbers, of the same types, as the numpy path gives."""

from __future__ import annotations

import random
from dataclasses import astuple
from typing import Any

import numpy as np
import orjson
import pytest

from twinlink.domain.samples import Value
from twinlink.store.sqlite.history import codec
from twinlink.store.sqlite.history.codec import (
    decode_times,
    decode_values,
    encode,
    kind_of,
    split_signals,
)

T = 1_704_067_200 * 10**9  # 2024-01-01T00:00:00Z in ns


def _values(rng: random.Random, kind: str, n: int) -> list[Any]:
    pick: dict[str, list[Any]] = {
        "i": [rng.randint(-(2**63), 2**63 - 1), rng.randint(-5, 5), 0],
        "f": [rng.uniform(-1e300, 1e300), rng.random(), 0.0, -0.0, float(rng.randint(-3, 3))],
        "b": [True, False],
        "mixed numbers": [1, 2.5, 2**62, -0.0],
        "j": ["a", 1, True, 2.5, "a,b"],
    }
    return [rng.choice(pick[kind]) for _ in range(n)]


@pytest.mark.parametrize("kind", ["i", "f", "b", "mixed numbers", "j"])
def test_small_blocks_are_packed_as_numpy_packs_them(
    kind: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = random.Random(kind)
    for _ in range(2000):
        n = rng.randint(1, codec.SMALL_BLOCK - 1)
        near = 1_732_200_000_000_000_000
        times = [
            rng.choice([rng.randint(-(2**62), 2**62), near + rng.randint(0, 3)]) for _ in range(n)
        ]
        values = _values(rng, kind, n)
        small = codec.encode("s", list(times), list(values))
        with monkeypatch.context() as m:
            m.setattr(codec, "SMALL_BLOCK", 0)  # the numpy path for every size
            wide = codec.encode("s", list(times), list(values))
        assert astuple(small) == astuple(wide), (times, values)
        assert [type(x) for x in astuple(small)] == [type(x) for x in astuple(wide)]


@pytest.mark.parametrize(
    ("values", "kind"),
    [
        ([1, 2, -3], "i"),
        ([1.5, 2.0], "f"),
        ([1, 2.5, 3], "f"),
        ([True, False], "b"),
        (["a", "b"], "j"),
        (["a", 1], "j"),
        ([True, 1], "j"),
        ([False, 1.5], "j"),
        ([True, 1, 2.5], "j"),
    ],
)
def test_kind_of(values: list[Value], kind: str) -> None:
    assert kind_of(values) == kind


def test_split_signals_makes_one_column_per_signal() -> None:
    columns = split_signals([1, 2, 3], [{"a": 1, "b": "x"}, {"a": 2}, {"b": "y", "c": True}])
    assert columns == {
        "a": ([1, 2], [1, 2]),
        "b": ([1, 3], ["x", "y"]),
        "c": ([3], [True]),
    }


def test_split_signals_needs_one_row_per_time() -> None:
    with pytest.raises(ValueError):
        split_signals([1, 2], [{"a": 1}])


def test_int_block_round_trip_and_summary() -> None:
    block = encode("n", [T, T + 1, T + 2], [5, -(2**63), 2**63 - 1])
    assert block.kind == "i"
    assert (block.signal, block.t0, block.t1, block.n) == ("n", T, T + 2, 3)
    assert decode_times(block.times).tolist() == [T, T + 1, T + 2]
    values = decode_values("i", block.vals)
    assert values.dtype == np.int64
    assert values.tolist() == [5, -(2**63), 2**63 - 1]
    assert (block.vmin, block.vmax) == (float(-(2**63)), float(2**63 - 1))
    assert (block.first_v, block.last_v) == (5, 2**63 - 1)
    assert len(block.times) == 3 * 8 and len(block.vals) == 3 * 8


def test_float_block_round_trip_and_summary() -> None:
    block = encode("x", [T, T + 1, T + 2, T + 3], [0.5, -1.25, 3.0, 2.0])
    assert block.kind == "f"
    assert decode_values("f", block.vals).tolist() == [0.5, -1.25, 3.0, 2.0]
    assert (block.vmin, block.vmax, block.vsum) == (-1.25, 3.0, 4.25)
    assert (block.first_v, block.last_v) == (0.5, 2.0)


def test_mixed_int_and_float_is_stored_as_float() -> None:
    block = encode("x", [T, T + 1, T + 2], [1, 2.5, 3])
    assert block.kind == "f"
    values = decode_values("f", block.vals)
    assert values.dtype == np.float64
    assert values.tolist() == [1.0, 2.5, 3.0]
    assert (block.vmin, block.vmax, block.vsum) == (1.0, 3.0, 6.5)


def test_bool_block_round_trip_and_summary() -> None:
    block = encode("on", [T, T + 1, T + 2], [True, False, True])
    assert block.kind == "b"
    values = decode_values("b", block.vals)
    assert values.dtype == np.bool_
    assert values.tolist() == [True, False, True]
    assert len(block.vals) == 3  # one byte per value
    assert (block.vmin, block.vmax, block.vsum) == (0.0, 1.0, 2.0)
    assert (block.first_v, block.last_v) == (True, True)


def test_string_block_is_json_without_numeric_summary() -> None:
    block = encode("state", [T, T + 1], ["idle", "run ✓"])
    assert block.kind == "j"
    assert decode_values("j", block.vals).tolist() == ["idle", "run ✓"]
    assert orjson.loads(block.vals) == ["idle", "run ✓"]
    assert (block.vmin, block.vmax, block.vsum) == (None, None, None)
    assert (block.first_v, block.last_v) == ("idle", "run ✓")


def test_mixed_bool_and_number_keeps_each_type_in_json() -> None:
    block = encode("m", [T, T + 1, T + 2], [True, 1, 2.5])
    assert block.kind == "j"
    decoded = decode_values("j", block.vals).tolist()
    assert decoded == [True, 1, 2.5]
    assert [type(v) for v in decoded] == [bool, int, float]
    assert block.vsum is None


def test_unsorted_times_are_sorted_stably_with_their_values() -> None:
    block = encode("x", [T + 3, T + 1, T + 2, T + 1, T], [30, 10, 20, 11, 0])
    assert decode_times(block.times).tolist() == [T, T + 1, T + 1, T + 2, T + 3]
    # equal times keep their arrival order (10 before 11)
    assert decode_values("i", block.vals).tolist() == [0, 10, 11, 20, 30]
    assert (block.t0, block.t1) == (T, T + 3)
    assert (block.first_v, block.last_v) == (0, 30)


def test_unsorted_json_values_follow_their_times() -> None:
    block = encode("s", [T + 2, T, T + 1], ["c", "a", "b"])
    assert decode_times(block.times).tolist() == [T, T + 1, T + 2]
    assert decode_values("j", block.vals).tolist() == ["a", "b", "c"]
    assert (block.first_v, block.last_v) == ("a", "c")


def test_a_single_sample_block() -> None:
    block = encode("x", [T], [7.5])
    assert (block.t0, block.t1, block.n) == (T, T, 1)
    assert (block.vmin, block.vmax, block.vsum, block.first_v, block.last_v) == (
        7.5,
        7.5,
        7.5,
        7.5,
        7.5,
    )
