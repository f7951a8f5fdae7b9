"""Export of PostgreSQL history as CSV, JSON lines or a JSON array, in constant memory.

The rows come a page at a time (reads.sample_page: an index range scan per page, the next
page from the key of the first row not given), so neither this process nor the server
holds more than one page; they leave as text in pieces of about 64 KiB. A client that stops
reading stops the export within a page.
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable, Iterator
from datetime import UTC, datetime
from typing import Any

import orjson

from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.history.budget import ReadBudget, reading
from twinlink.store.postgres.history.reads import sample_page
from twinlink.store.postgres.history.series import Selection

PAGE_ROWS = 5_000
_PIECE = 64 * 1024


def iso_time(ns: int) -> str:
    """ISO 8601 in UTC with nanoseconds: 2026-11-21T10:00:00.123456789Z."""
    seconds, fraction = divmod(ns, 10**9)
    moment = datetime.fromtimestamp(seconds, UTC)
    return f"{moment:%Y-%m-%dT%H:%M:%S}.{fraction:09d}Z"


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


def _csv(
    rows: list[dict[str, Any]], names: list[str], time: Callable[[int], Any]
) -> Iterator[bytes]:
    for row in rows:
        values = row["values"]
        cells = [csv_cell(values[n]) if n in values else "" for n in names]
        yield (f"{time(row['time'])}," + ",".join(cells) + "\n").encode()


def _jsonl(rows: list[dict[str, Any]], _: list[str], time: Callable[[int], Any]) -> Iterator[bytes]:
    for row in rows:
        yield orjson.dumps({"time": time(row["time"]), "values": row["values"]}) + b"\n"


async def export_pieces(
    db: PostgresDatabase,
    found: Selection,
    start: int,
    end: int,
    fmt: str,
    time_format: str,
    budget: ReadBudget,
) -> AsyncIterator[bytes]:
    names = found.names
    time: Callable[[int], Any] = iso_time if time_format == "iso" else (lambda t: t)
    if fmt == "csv":
        time = time if time_format == "iso" else str
    buffer: list[bytes] = []
    size = 0
    if fmt == "csv":
        buffer.append(("time," + ",".join(names) + "\n").encode())
    separator = b"[\n"
    after: tuple[int, int] | None = None
    while True:
        async with reading(db, budget) as conn:
            page = await sample_page(conn, found, start, end, PAGE_ROWS, after)
        texts = (_csv if fmt == "csv" else _jsonl)(page.rows, names, time)
        for text in texts:
            if fmt == "json":
                text, separator = separator + text.rstrip(b"\n"), b",\n"
            buffer.append(text)
            size += len(text)
            if size >= _PIECE:
                yield b"".join(buffer)
                buffer, size = [], 0
        if page.next_key is None:
            break
        after = page.next_key
    if fmt == "json":
        buffer.append(b"[]\n" if separator == b"[\n" else b"\n]\n")
    if buffer:
        yield b"".join(buffer)
