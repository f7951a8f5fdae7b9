"""Ranges of the numbers routes take, declared once so they show in OpenAPI and are checked
before a handler runs.

Ids are SQLite row ids (1 to 2^63-1; a larger one makes the driver raise OverflowError), times
are ns since the epoch in int64 (1970 to 2262), and durations have a maximum a person would
mean, so no product of them overflows an int64 of nanoseconds.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import Path, Query

from twinlink.domain.jsontext import INT64_MAX

# The last second whose nanoseconds fit in an int64 (2262-04-11T23:47:16Z).
MAX_UNIX_S = INT64_MAX // 1_000_000_000

RowId = Annotated[int, Path(ge=1, le=INT64_MAX, description="the id (1 to 2^63-1)")]
OlderThan = Annotated[
    int | None,
    Query(ge=1, le=INT64_MAX, description="only entries with a smaller id (the last page's)"),
]
UnixSeconds = Annotated[
    float | None,
    Query(
        ge=0,
        le=MAX_UNIX_S,
        allow_inf_nan=False,
        description=f"Unix time in seconds, 0 to {MAX_UNIX_S} (2262)",
    ),
]
HttpStatus = Annotated[int | None, Query(ge=100, le=599, description="an HTTP status code")]
