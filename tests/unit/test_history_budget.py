"""Reads under a budget (issue 13): a read over its time or its values stops with a clear
error, an export whose reader leaves stops its work at once (also through the ASGI response,
as when an HTTP client disconnects), and closing the history stops running reads instead of
waiting for them."""

from __future__ import annotations

import asyncio
import sqlite3
import time
from pathlib import Path
from typing import Any

import pytest

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import sqlite_history as sqlite_history  # fixture
from twinlink.api.history import ExportResponse
from twinlink.domain.history import (
    MAX_TIME,
    MIN_TIME,
    QueryTimeoutError,
    QueryTooLargeError,
    ReadCancelledError,
)
from twinlink.store.sqlite.history import ReadLimits, SqliteHistory
from twinlink.store.sqlite.history.budget import ReadBudget

# A statement that never ends by itself: only an interrupt stops it.
FOREVER = "WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c) SELECT count(*) FROM c"


def forever(conn: sqlite3.Connection) -> Any:
    return conn.execute(FOREVER).fetchone()


async def until(check: Any, what: str, timeout_s: float = 10.0) -> None:
    """Poll a condition of the real state until it holds (the deadline bounds a hang)."""
    deadline = time.monotonic() + timeout_s
    while not check():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        await asyncio.sleep(0.01)


async def test_a_read_over_its_time_is_stopped_with_the_setting_to_change(
    sqlite_history: SqliteHistory,
) -> None:
    with pytest.raises(QueryTimeoutError, match=r"TWINLINK_HISTORY_QUERY_TIMEOUT_S \(0\.05 s\)"):
        await sqlite_history.reader.run(forever, ReadBudget(0.05, 10))
    await write(sqlite_history, [(T, {"x": 1.0})])
    assert (await sqlite_history.latest(TWIN, STREAM, None))["x"][
        "value"
    ] == 1.0  # the pool is fine


async def test_closing_stops_running_reads_instead_of_waiting(
    sqlite_history: SqliteHistory,
) -> None:
    running = asyncio.ensure_future(sqlite_history.reader.run(forever, ReadBudget(3600, 10)))
    await until(lambda: sqlite_history.reader.steps == 1, "the read to start")
    await asyncio.wait_for(sqlite_history.reader.close(), 10)
    with pytest.raises(ReadCancelledError, match="shutting down"):
        await running
    with pytest.raises(ReadCancelledError):  # and no read starts after
        await sqlite_history.latest(TWIN, STREAM, None)


async def many_pieces(history: SqliteHistory) -> None:
    times = [T + i * 10**6 for i in range(200_000)]
    await write_column(history, "a", times, [float(i) for i in range(200_000)], 20_000)


async def test_an_export_whose_reader_stops_stops_its_work(sqlite_history: SqliteHistory) -> None:
    await many_pieces(sqlite_history)
    _, pieces = await sqlite_history.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "jsonl", "ns")
    assert b'"a":0.0' in await anext(pieces)  # type: ignore[call-overload]
    assert sqlite_history.reader.open_streams == 1
    await pieces.aclose()  # type: ignore[attr-defined]
    await until(lambda: sqlite_history.reader.open_streams == 0, "the export to close")
    steps = sqlite_history.reader.steps
    assert steps <= 3  # the whole export is about 90 pieces: it stopped after the first
    await write(sqlite_history, [(T, {"b": 1})])  # the reader still works for others
    assert (await sqlite_history.latest(TWIN, STREAM, ["b"]))["b"]["value"] == 1


async def test_a_client_that_disconnects_stops_the_export(sqlite_history: SqliteHistory) -> None:
    await many_pieces(sqlite_history)
    _, pieces = await sqlite_history.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "csv", "iso")
    response = ExportResponse(pieces, "csv", "text/csv", "x.csv")
    sent: list[dict[str, Any]] = []
    gone = asyncio.Event()

    async def receive() -> dict[str, Any]:
        await gone.wait()
        return {"type": "http.disconnect"}

    async def send(message: dict[str, Any]) -> None:
        sent.append(message)
        if message.get("body"):
            gone.set()  # the client leaves after the first piece

    scope = {"type": "http", "asgi": {"spec_version": "2.3"}}
    await asyncio.wait_for(response(scope, receive, send), 10)
    await until(lambda: sqlite_history.reader.open_streams == 0, "the export to close")
    assert sent[0]["type"] == "http.response.start"
    assert all(m.get("more_body", True) for m in sent)  # never finished
    assert sqlite_history.reader.steps <= 3


async def test_an_export_over_its_time_is_cut_visibly(tmp_path: Path) -> None:
    h = SqliteHistory(tmp_path, "normal", limits=ReadLimits(export_timeout_s=1e-9))
    await h.open()
    try:
        await write(h, [(T, {"x": 1})])
        _, pieces = await h.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "jsonl", "ns")
        sent: list[dict[str, Any]] = []

        async def send(message: dict[str, Any]) -> None:
            sent.append(message)

        async def receive() -> dict[str, Any]:
            await asyncio.Event().wait()  # the client stays
            return {}

        response = ExportResponse(pieces, "jsonl", "application/jsonl", "x.jsonl")
        await response({"type": "http", "asgi": {"spec_version": "2.4"}}, receive, send)
        bodies = [m["body"] for m in sent[1:]]
        assert b"TWINLINK_HISTORY_EXPORT_TIMEOUT_S" in bodies[-1]  # the last line says why
        assert bodies[-1].startswith(b'{"error":')
        assert all(m["more_body"] for m in sent[1:])  # and the body never ends
    finally:
        await h.close()


async def test_answers_over_the_values_budget(tmp_path: Path) -> None:
    h = SqliteHistory(tmp_path, "normal", limits=ReadLimits(max_values=10))
    await h.open()
    try:
        await write(h, [(T + i * S, {"a": i, "b": float(i), "c": i % 2 == 0}) for i in range(8)])
        with pytest.raises(QueryTooLargeError, match=r"aggregate would hold 24 values.*at most 10"):
            await h.aggregate(TWIN, STREAM, None, T, T + 10 * S, S, ["avg"])
        with pytest.raises(QueryTooLargeError, match="downsample would hold 24 values"):
            await h.downsample(TWIN, STREAM, None, T, T + 10 * S, 100, "minmax")
        assert len((await h.aggregate(TWIN, STREAM, ["a"], T, T + 10 * S, S, ["avg"])).rows) == 8
        # a page of samples stops at the budget (3 rows of 3 values) and goes on after it
        rows, after = [], None
        while True:
            page = await h.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 100, after)
            assert len(page.rows) == (3 if page.next_key else 2)
            rows.extend(page.rows)
            if page.next_key is None:
                break
            after = page.next_key
        assert [r["values"]["a"] for r in rows] == list(range(8))
    finally:
        await h.close()
