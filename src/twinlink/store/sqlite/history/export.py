"""Export of a range as CSV, JSON lines or a JSON array, streamed in constant memory.

The rows come from the merge (merge.py) a page at a time and leave as text in pieces of about
64 KiB; nothing holds more than one page of blocks and its text. Each piece is one step of
the read (reader.py), so a client that stops reading stops the work within a page.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Callable, Generator, Iterable, Iterator
from typing import Any

import numpy as np
import orjson

from twinlink.store.sqlite.history.budget import ReadBudget
from twinlink.store.sqlite.history.columns import Times
from twinlink.store.sqlite.history.merge import Rows, joined_rows
from twinlink.store.sqlite.history.queries import Series

_PIECE = 64 * 1024


def iso_times(times: Times) -> list[str]:
    """ISO 8601 in UTC with nanoseconds: 2026-11-21T10:00:00.123456789Z."""
    text = np.datetime_as_string(times.astype("datetime64[ns]"), unit="ns", timezone="UTC")
    return text.tolist()  # type: ignore[no-any-return]


def _time_texts(times: Times, time_format: str) -> list[str]:
    return iso_times(times) if time_format == "iso" else list(map(str, times.tolist()))


def csv_cell(value: Any) -> str:
    if value is True:
        return "true"
    if value is False:
        return "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        if any(c in value for c in ',"\r\n'):
            return '"' + value.replace('"', '""') + '"'
        return value
    return str(value)


_CELL: dict[type, Callable[[Any], str]] = {  # by type: one dict lookup a value
    bool: lambda v: "true" if v else "false",
    int: str,
    float: repr,
    str: csv_cell,
}
_CSV_CELLS = 1 << 20  # cells of one block of CSV lines: rows x signals, empty ones included


def csv_text(rows: Rows, time_format: str, width: int) -> Iterator[str]:
    """The rows as CSV lines (time, then one cell per signal of the `width` signals, empty
    where it has no value), in blocks of about a million cells."""
    cells = np.asarray(
        [_CELL.get(type(v), csv_cell)(v) for v in rows.values.tolist()], dtype=object
    )
    times = _time_texts(rows.times, time_format)
    step = max(1, _CSV_CELLS // max(1, width))
    sizes = np.diff(rows.starts)
    for lo in range(0, len(rows), step):
        hi = min(len(rows), lo + step)
        a, b = int(rows.starts[lo]), int(rows.starts[hi])
        grid = np.full((hi - lo, width + 1), "", dtype=object)
        grid[:, 0] = times[lo:hi]
        grid[np.repeat(np.arange(hi - lo), sizes[lo:hi]), rows.series[a:b] + 1] = cells[a:b]
        yield "".join(",".join(line) + "\n" for line in grid.tolist())


def _pieces(texts: Iterable[bytes]) -> Iterator[bytes]:
    """Join small texts into pieces of about 64 KiB."""
    buffer: list[bytes] = []
    size = 0
    for text in texts:
        buffer.append(text)
        size += len(text)
        if size >= _PIECE:
            yield b"".join(buffer)
            buffer, size = [], 0
    if buffer:
        yield b"".join(buffer)


def _csv(runs: Iterator[Rows], names: list[str], time_format: str) -> Iterator[bytes]:
    yield ("time," + ",".join(names) + "\n").encode()
    for rows in runs:
        for text in csv_text(rows, time_format, len(names)):
            yield text.encode()


def _dicts(runs: Iterator[Rows], names: list[str], time_format: str) -> Iterator[dict[str, Any]]:
    for rows in runs:
        dicts = rows.as_dicts(names)
        if time_format == "iso":
            for row, text in zip(dicts, iso_times(rows.times), strict=True):
                row["time"] = text
        yield from dicts


def _jsonl(runs: Iterator[Rows], names: list[str], time_format: str) -> Iterator[bytes]:
    for row in _dicts(runs, names, time_format):
        yield orjson.dumps(row) + b"\n"


def _json(runs: Iterator[Rows], names: list[str], time_format: str) -> Iterator[bytes]:
    separator = b"[\n"
    for row in _dicts(runs, names, time_format):
        yield separator + orjson.dumps(row)
        separator = b",\n"
    yield b"[]\n" if separator == b"[\n" else b"\n]\n"


_WRITERS = {"csv": _csv, "jsonl": _jsonl, "json": _json}


def export_pieces(
    conn: sqlite3.Connection,
    series: list[Series],
    start: int,
    end: int,
    fmt: str,
    time_format: str,
    budget: ReadBudget,
) -> Generator[bytes, None, None]:
    """The range as `fmt` text, in pieces of about 64 KiB."""
    runs = joined_rows(conn, series, start, end, budget)
    try:
        yield from _pieces(_WRITERS[fmt](runs, [s.signal for s in series], time_format))
    finally:
        runs.close()
