"""Helpers for the history tests: the store under test in tmp_path, and writing rows through
its real write path. A module opts in to a fixture by importing it
(`from tests.unit._history import history as history`).

`history` is a `HistoryStore` of every backend in turn (`_storage.BACKENDS`): tests that take
it check behaviour any backend must have, through the protocol only. `sqlite_history` is the
SQLite store, for tests of its own workings (blocks, staging, sketches, the WAL).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest

from tests.unit._storage import BACKENDS
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.history import HistoryStore, HistoryWriterStore
from twinlink.store.sqlite.history import SqliteHistory

T = 1_704_067_200 * 10**9  # 2024-01-01T00:00:00Z in ns
S = 10**9  # one second in ns
TWIN = 7
STREAM = "telemetry"


@pytest.fixture(params=list(BACKENDS))
async def history(request: pytest.FixtureRequest, tmp_path: Path) -> AsyncIterator[HistoryStore]:
    async with BACKENDS[request.param].history(tmp_path) as store:
        yield store


@pytest.fixture
async def sqlite_history(tmp_path: Path) -> AsyncIterator[SqliteHistory]:
    h = SqliteHistory(tmp_path / "data", "normal")
    await h.open()
    try:
        yield h
    finally:
        await h.close()


async def write(
    history: HistoryWriterStore,
    rows: list[tuple[int, dict[str, Value]]],
    *,
    twin_id: int = TWIN,
    stream: str = STREAM,
) -> None:
    """One batch: each row is (time, {signal: value}); each signal becomes one block."""
    batch = SampleBatch(
        twin_id=twin_id,
        twin=f"twin{twin_id}",
        stream=stream,
        times=[t for t, _ in rows],
        values=[v for _, v in rows],
        received_ns=T,
    )
    await history.append(batch)


async def write_column(
    history: HistoryWriterStore, signal: str, times: list[int], values: list[Any], block: int
) -> None:
    """One signal's samples, `block` samples per batch (so per block)."""
    for i in range(0, len(times), block):
        rows = zip(times[i : i + block], values[i : i + block], strict=True)
        await write(history, [(t, {signal: v}) for t, v in rows])
