"""Export as CSV, JSON lines and a JSON array: formatting, and a streamed range equal to the
rows of the range query."""

from __future__ import annotations

import csv
import io

import numpy as np
import orjson

from tests.unit._history import STREAM, TWIN, S, T, write, write_column
from tests.unit._history import history as history  # fixture
from twinlink.domain.history import MAX_TIME, MIN_TIME
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite.history.export import csv_cell, iso_times


async def export(history: HistoryStore, fmt: str, time_format: str, **kw: object) -> bytes:
    signals = kw.get("signals")
    start, end = kw.get("start", MIN_TIME), kw.get("end", MAX_TIME)
    _, pieces = await history.export(TWIN, STREAM, signals, start, end, fmt, time_format)  # type: ignore[arg-type]
    return b"".join([piece async for piece in pieces])


def test_csv_cells() -> None:
    assert [csv_cell(v) for v in (True, False, 3, -2.5, 1e-7, "plain")] == [
        "true",
        "false",
        "3",
        "-2.5",
        "1e-07",
        "plain",
    ]
    assert csv_cell('say "hi", then\nleave') == '"say ""hi"", then\nleave"'


def test_iso_times_have_nanoseconds_and_z() -> None:
    times = np.array([T, T + 123_456_789, 0], dtype=np.int64)
    assert iso_times(times) == [
        "2024-01-01T00:00:00.000000000Z",
        "2024-01-01T00:00:00.123456789Z",
        "1970-01-01T00:00:00.000000000Z",
    ]


async def test_csv_has_a_header_iso_times_and_empty_cells(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1.5, "n": 2}), (T + 1, {"x": 2.0, "note": 'a "b", c'})])
    await write(history, [(T + S, {"on": True})])
    text = (await export(history, "csv", "iso")).decode()
    assert text.splitlines()[0] == "time,n,note,on,x"
    assert list(csv.reader(io.StringIO(text)))[1:] == [
        ["2024-01-01T00:00:00.000000000Z", "2", "", "", "1.5"],
        ["2024-01-01T00:00:00.000000001Z", "", 'a "b", c', "", "2.0"],
        ["2024-01-01T00:00:01.000000000Z", "", "", "true", ""],
    ]
    ns = (await export(history, "csv", "ns", signals=["x"])).decode().splitlines()
    assert ns == ["time,x", f"{T},1.5", f"{T + 1},2.0"]


async def test_jsonl_and_json_array(history: HistoryStore) -> None:
    await write(history, [(T, {"x": 1, "s": "a"}), (T + S, {"x": 2})])
    lines = (await export(history, "jsonl", "ns")).splitlines()
    assert [orjson.loads(line) for line in lines] == [
        {"time": T, "values": {"s": "a", "x": 1}},
        {"time": T + S, "values": {"x": 2}},
    ]
    array = orjson.loads(await export(history, "json", "iso"))
    assert array == [
        {"time": "2024-01-01T00:00:00.000000000Z", "values": {"s": "a", "x": 1}},
        {"time": "2024-01-01T00:00:01.000000000Z", "values": {"x": 2}},
    ]
    assert orjson.loads(await export(history, "json", "ns", start=T + 10 * S)) == []
    assert await export(history, "jsonl", "ns", start=T + 10 * S) == b""


async def test_a_large_range_streams_in_pieces_equal_to_the_rows(history: HistoryStore) -> None:
    n = 30_000
    rng = np.random.default_rng(2)
    times = (T + np.cumsum(rng.integers(0, 3, n)) * 10**6).tolist()  # some equal times
    await write_column(history, "a", times, rng.normal(size=n).tolist(), 3000)
    await write_column(history, "b", times[::3], list(range(len(times[::3]))), 700)
    await write_column(history, "a", times[5::50], [0.0] * len(times[5::50]), 100)  # late
    _, pieces = await history.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "jsonl", "ns")
    sizes, rows = [], []
    async for piece in pieces:
        sizes.append(len(piece))
        rows.extend(orjson.loads(line) for line in piece.splitlines())
    assert len(sizes) > 10 and max(sizes) < 1_000_000  # pieces, not one answer
    page = await history.samples(TWIN, STREAM, None, MIN_TIME, MAX_TIME, 10**6)
    assert rows == page.rows
    assert sum(len(r["values"]) for r in rows) == n + len(times[::3]) + len(times[5::50])


async def test_stopping_early_closes_the_export(history: HistoryStore) -> None:
    await write_column(history, "a", [T + i for i in range(50_000)], [1.0] * 50_000, 5000)
    _, pieces = await history.export(TWIN, STREAM, None, MIN_TIME, MAX_TIME, "csv", "iso")
    first = await anext(pieces)  # type: ignore[call-overload]
    assert first.startswith(b"time,a\n")
    await pieces.aclose()  # type: ignore[attr-defined]
    # the history can still be read and closed afterwards (the fixture closes it)
    assert (await history.latest(TWIN, STREAM, None))["a"]["value"] == 1.0
