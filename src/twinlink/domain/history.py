"""What a history query may ask for and what it gets back, whatever stores the samples.

The choices the API offers (aggregate functions, downsampling methods, export formats), the
open bounds of a time range, the result types of `HistoryStore` (store/history.py), and the
errors of a read that stops before its end. Times are integer ns since the epoch; `start` and
`end` are inclusive, and MIN_TIME/MAX_TIME stand for "no bound".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from twinlink.domain.errors import TwinlinkError

MIN_TIME = -(2**63)
MAX_TIME = 2**63 - 1

FUNCTIONS = ("avg", "min", "max", "count", "first", "last", "sum")  # of aggregate
METHODS = ("minmax", "lttb")  # of downsample
FORMATS = ("csv", "jsonl", "json")  # of export
TIME_FORMATS = ("iso", "ns")  # of an export's times
MEDIA_TYPES = {
    "csv": "text/csv; charset=utf-8",
    "jsonl": "application/jsonl",
    "json": "application/json",
}


@dataclass(slots=True)
class SamplePage:
    rows: list[dict[str, Any]]  # {time, values: {signal: value}}, in time order
    next_key: tuple[int, int] | None  # (time, occurrence) of the first row not given


@dataclass(slots=True)
class Aggregated:
    rows: list[dict[str, Any]]  # {time: bucket start, values: {signal: {fn: value}}}
    text_only: list[str]  # signals with samples in range, none of them numeric


@dataclass(slots=True)
class Downsampled:
    times: npt.NDArray[np.int64]
    values: npt.NDArray[Any]  # int64 for a signal of integers (exact), else float64
    text_only: bool  # the signal has samples in range, and none of them is numeric


@dataclass(slots=True)
class Compaction:
    """What one round of background compaction did, in the store's own units of storage
    (SQLite: blocks); zeros for a store that needs none."""

    before: int = 0
    after: int = 0


class ReadBudgetError(TwinlinkError):
    """A read stopped before its end; the message says why and what to change. A read over
    its time, or stopped by a shutdown, may succeed later."""

    status = 503


class QueryTooLargeError(ReadBudgetError):
    """The answer would hold more values than a read may: narrow the query."""

    status = 422


class QueryTimeoutError(ReadBudgetError):
    """The read ran longer than it may."""


class ReadCancelledError(ReadBudgetError):
    """The read was stopped from outside: its client left, or the server is shutting down."""
