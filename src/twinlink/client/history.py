"""A twin's stored samples as a pandas DataFrame: one row per time, one column per signal.

pandas is imported when a DataFrame is asked for, so the rest of the client works without it.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import TYPE_CHECKING, Any

from twinlink.client._http import Transport

if TYPE_CHECKING:
    import pandas

# The most rows the history API gives in one page: fewer round trips for long ranges.
PAGE_ROWS = 100_000
Time = str | int | datetime | None


def time_param(value: Time) -> str | None:
    """A time as the history API takes it: ISO 8601, integer ns, `now` or `-1h` as given;
    a datetime (or pandas Timestamp) in ISO 8601, a naive one taken as UTC."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, bool):
        raise TypeError("a time is a datetime, integer ns or text, not a bool")
    if isinstance(value, int):
        return str(value)
    if value.tzinfo is None:
        value = value.replace(tzinfo=UTC)
    return value.isoformat()


def read_rows(
    transport: Transport,
    twin: str,
    stream: str,
    start: Time,
    end: Time,
    signals: list[str] | None,
) -> tuple[list[int], list[dict[str, Any]]]:
    """Every row in the range, following `next_cursor` page by page: (times, values)."""
    params: dict[str, Any] = {
        "limit": PAGE_ROWS,
        "start": time_param(start),
        "end": time_param(end),
    }
    if signals:
        params["signals"] = ",".join(signals)
    params = {k: v for k, v in params.items() if v is not None}
    times: list[int] = []
    values: list[dict[str, Any]] = []
    path = f"/api/v1/twins/{twin}/streams/{stream}/samples"
    while True:
        page = transport.json("GET", path, params=params)
        for row in page["rows"]:
            times.append(row["time"])
            values.append(row["values"])
        if not page.get("next_cursor"):
            return times, values
        params["cursor"] = page["next_cursor"]


def to_frame(
    times: list[int], values: list[dict[str, Any]], signals: list[str] | None
) -> pandas.DataFrame:
    import pandas as pd  # lazily: only DataFrames need it

    index = pd.DatetimeIndex(pd.to_datetime(times, unit="ns", utc=True), name="time")
    if not values:
        return pd.DataFrame(index=index, columns=signals or [])
    frame = pd.DataFrame.from_records(values, index=index)
    if signals:  # in the order asked for, a signal without values an empty column
        frame = frame.reindex(columns=signals)
    return frame
