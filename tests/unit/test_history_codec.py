"""Blocks of fewer than SMALL_BLOCK samples are packed without numpy: the same bytes and
numbers, of the same types, as the numpy path gives."""

from __future__ import annotations

import random
from dataclasses import astuple
from typing import Any

import pytest

from twinlink.store.sqlite.history import codec


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
