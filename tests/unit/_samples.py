"""Helpers for the sample-batch tests (test_samples_*.py): a batch read at a fixed clock."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from twinlink.domain.samples import OPEN_SCHEMA, ReadBatch, Schema, SignalRule, read_batch

NOW = 1_700_000_000_000_000_000  # 2023-11-14T22:13:20Z in ns
T2024 = 1_704_067_200  # 2024-01-01T00:00:00Z in s
EARLIEST_NS = 631_152_000 * 10**9  # 1990-01-01T00:00:00Z
LATEST_NS = 7_258_118_400 * 10**9  # 2200-01-01T00:00:00Z
TINGEN = Path(__file__).resolve().parents[2] / "examples" / "tingen" / "tingen.yaml"


def read(samples: list[Any], schema: Schema = OPEN_SCHEMA, **batch: Any) -> ReadBatch:
    return read_batch({"seq": 1, "samples": samples, **batch}, schema, NOW)


def one(sample: dict[str, Any], schema: Schema = OPEN_SCHEMA, **batch: Any) -> ReadBatch:
    return read([sample], schema, **batch)


def reason(sample: dict[str, Any], schema: Schema = OPEN_SCHEMA, **batch: Any) -> str:
    """The reason the only sample of a batch was rejected (fails if it was kept)."""
    out = one(sample, schema, **batch)
    assert out.times == []
    assert len(out.rejected) == 1
    assert out.rejected[0].index == 0
    return out.rejected[0].reason


def schema(unknown: str = "accept", out_of_range: str = "reject", **rules: SignalRule) -> Schema:
    return Schema(rules, unknown, out_of_range)  # type: ignore[arg-type]


def num(lo: float | None = None, hi: float | None = None) -> SignalRule:
    return SignalRule("number", lo, hi)
