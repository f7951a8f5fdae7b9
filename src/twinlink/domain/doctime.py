"""The times a DT document brings (`createdMachine`, `createdHuman`, ...), read into the one
form twinlink keeps a time in: a 64-bit count of nanoseconds since 1970 (UTC), and that
count back into the text the API shows (`human_time`).

That count holds the times from 1677-09-21T00:12:43.145224192Z to 2262-04-11T23:47:16.854775807Z.
A document's time outside that span cannot be kept; it is refused with the span named, never
left to overflow in the store. A value that does not read as a time at all (`soon`) is not a
range problem: callers decide what to do with None.
"""

from __future__ import annotations

from datetime import UTC, datetime
from decimal import Decimal, InvalidOperation
from typing import Any

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.jsontext import INT64_MAX, INT64_MIN

NS = 1_000_000_000
_EPOCH = datetime(1970, 1, 1, tzinfo=UTC)
# Whole seconds inside the span, as people read them, and the exact bounds.
FIRST_SECOND = -(-INT64_MIN // NS)  # -9223372036
LAST_SECOND = INT64_MAX // NS  # 9223372036
_LOWEST = Decimal(INT64_MIN).scaleb(-9)
_HIGHEST = Decimal(INT64_MAX).scaleb(-9)
SPAN_HUMAN = "1677-09-21T00:12:44Z to 2262-04-11T23:47:16Z"
SPAN_MACHINE = f"Unix seconds from {FIRST_SECOND} to {LAST_SECOND} ({SPAN_HUMAN})"


class TimeRangeError(TwinlinkError, ValueError):
    """A time that reads well but lies outside what 64-bit nanoseconds hold; the message
    names the span."""


def machine_ns(value: Any) -> int | None:
    """Unix seconds (a number, or a number written as text) as nanoseconds; None when the value
    is not a number. Raises TimeRangeError for a number outside the span (or not finite)."""
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        return None
    try:
        seconds = Decimal(value.strip() if isinstance(value, str) else repr(value))
    except (InvalidOperation, ValueError):
        return None
    # Compared as a decimal before anything is multiplied: `1e999999` must not be expanded.
    if not seconds.is_finite() or not _LOWEST <= seconds <= _HIGHEST:
        raise TimeRangeError(
            f"{_shown(value)} is outside the times twinlink can hold: {SPAN_MACHINE}"
        )
    return int(seconds.scaleb(9))


def human_ns(value: Any) -> int | None:
    """An ISO 8601 date or date and time (UTC when it names no zone) as nanoseconds; None when
    the value does not read as one. Raises TimeRangeError outside the span."""
    if not isinstance(value, str):
        return None
    try:
        moment = datetime.fromisoformat(value.strip())
    except ValueError:
        return None
    if moment.tzinfo is None:
        moment = moment.replace(tzinfo=UTC)
    since = moment - _EPOCH  # exact: a timedelta, never a float
    ns = (since.days * 86_400 + since.seconds) * NS + since.microseconds * 1000
    if not INT64_MIN <= ns <= INT64_MAX:
        raise TimeRangeError(
            f"{_shown(value)} is outside the times twinlink can hold: {SPAN_HUMAN}"
        )
    return ns


def human_time(ns: int) -> str:
    """The time as the API shows it: ISO 8601 in UTC, to the millisecond
    (`2026-11-21T10:00:00.123Z`)."""
    moment = datetime.fromtimestamp(ns / 1e9, tz=UTC)
    return moment.isoformat(timespec="milliseconds").replace("+00:00", "Z")


def _shown(value: Any) -> str:
    if not isinstance(value, str):
        return repr(value)
    return repr(value[:40] + "..." if len(value) > 40 else value)
