"""Reading the parameters of history queries: times, durations, names and choices.

Every refusal is a `QueryError` whose message names the parameter and says what would be
accepted, so the API can answer 422 with it as it is.
"""

from __future__ import annotations

import calendar
import re
from datetime import UTC, datetime

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.samples import SIGNAL_NAME

TIME_HELP = (
    "ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the "
    "epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`)"
)
DURATION_HELP = "a number and a unit: ns, us, ms, s, m, h, d or w (`500ms`, `1s`, `15m`, `1.5h`)"
UNIT_NS = {
    "ns": 1,
    "us": 1_000,
    "ms": 1_000_000,
    "s": 1_000_000_000,
    "m": 60_000_000_000,
    "h": 3_600_000_000_000,
    "d": 86_400_000_000_000,
    "w": 604_800_000_000_000,
}
# ASCII digits, and no more than int64 needs: `int()` of 4 300 digits raises, and
# `float()` of 400 gives inf.
_DURATION = re.compile(r"^([0-9]{1,20}(?:\.[0-9]{1,20})?)\s*(ns|us|ms|s|m|h|d|w)$")
_INTEGER = re.compile(r"^-?[0-9]{1,30}$")
_ISO = re.compile(
    r"^(?P<base>\d{4}-\d\d-\d\d(?:[T ]\d\d:\d\d(?::\d\d)?)?)"
    r"(?:\.(?P<fraction>\d{1,9}))?(?P<zone>Z|z|[+-]\d\d(?::?\d\d)?)?$"
)
# Integers below this (1973) are not ns since the epoch: most likely seconds or milliseconds.
_SMALLEST_NS = 10**17
_INT64 = 2**63


class QueryError(TwinlinkError, ValueError):
    """A parameter a person must fix; the message says how."""

    status = 422


def parse_duration(text: str, name: str) -> int:
    """A positive duration in ns."""
    match = _DURATION.match(text.strip())
    if match is None:
        raise QueryError(f"`{name}` {_short(text)!r} is not a duration: use {DURATION_HELP}")
    number, unit = match.groups()
    ns = round(float(number) * UNIT_NS[unit]) if "." in number else int(number) * UNIT_NS[unit]
    if not 0 < ns < _INT64:
        raise QueryError(f"`{name}` {text!r} must be more than 0 ns and less than 292 years")
    return ns


def parse_time(text: str | None, name: str, now_ns: int, default: int) -> int:
    """A time in ns since the epoch; `default` when the parameter is left out."""
    if text is None or not text.strip():
        return default
    text = text.strip()
    if text == "now":
        return now_ns
    if text.startswith("-") and not _INTEGER.match(text):
        return now_ns - parse_duration(text[1:], name)
    if text.lstrip("-").isdigit():
        if not _INTEGER.match(text):
            raise QueryError(f"`{name}` {_short(text)} is not a time: use {TIME_HELP}")
        value = int(text)
        if value >= _INT64:
            raise QueryError(f"`{name}` {text} is after 2262: use ns since the epoch")
        if value < _SMALLEST_NS:
            raise QueryError(
                f"`{name}` {text} is not a time in ns since the epoch (that would be before "
                f"1973; seconds or milliseconds?). Use {TIME_HELP}"
            )
        return value
    return _parse_iso(text, name)


def _parse_iso(text: str, name: str) -> int:
    match = _ISO.match(text)
    if match is None:
        raise QueryError(f"`{name}` {text!r} is not a time: use {TIME_HELP}")
    base, fraction, zone = match.group("base", "fraction", "zone")
    try:
        parsed = datetime.fromisoformat(base + (zone or "").replace("z", "Z"))
    except ValueError as err:
        raise QueryError(f"`{name}` {text!r} is not a valid time ({err})") from err
    if parsed.tzinfo is None:
        parsed = parsed.replace(tzinfo=UTC)
    seconds = calendar.timegm(parsed.utctimetuple())
    ns = seconds * 1_000_000_000 + int((fraction or "0").ljust(9, "0"))
    if not -_INT64 <= ns < _INT64:
        raise QueryError(f"`{name}` {text!r} is out of range: use a year from 1678 to 2261")
    return ns


def parse_names(text: str | None, name: str = "signals") -> list[str] | None:
    """A comma-separated list of signal names; None (every signal) when left out or empty."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    for n in names:
        if not SIGNAL_NAME.match(n):
            raise QueryError(f"`{name}`: {n!r} is not a signal name ({SIGNAL_NAME.pattern})")
    return names or None


def parse_choices(
    text: str | None, name: str, allowed: tuple[str, ...], default: list[str]
) -> list[str]:
    """A comma-separated list of words from `allowed`, in the order given, without repeats."""
    if text is None or not text.strip():
        return default
    chosen = [c.strip() for c in text.split(",") if c.strip()]
    wrong = [c for c in chosen if c not in allowed]
    if wrong:
        raise QueryError(
            f"`{name}`: {', '.join(map(repr, wrong))} not known; use one or more of "
            f"{', '.join(allowed)} (comma-separated)"
        )
    return list(dict.fromkeys(chosen))


def parse_choice(text: str | None, name: str, allowed: tuple[str, ...], default: str) -> str:
    if text is None or not text.strip():
        return default
    if text.strip() not in allowed:
        raise QueryError(f"`{name}` {text!r} is not known; use one of {', '.join(allowed)}")
    return text.strip()


def format_cursor(key: tuple[int, int]) -> str:
    return f"{key[0]}.{key[1]}"


def parse_cursor(text: str | None) -> tuple[int, int] | None:
    if text is None or not text.strip():
        return None
    time_text, _, rank_text = text.strip().partition(".")
    if _INTEGER.match(time_text) and _INTEGER.match(rank_text) and rank_text[0] != "-":
        key = int(time_text), int(rank_text)
        if -_INT64 <= key[0] < _INT64 and key[1] < _INT64:
            return key
    raise QueryError(
        f"`cursor` {_short(text)!r} is not a cursor: pass `next_cursor` of the previous page as is"
    )


def _short(text: str) -> str:
    """A parameter as sent, shortened for a message."""
    return text if len(text) <= 40 else f"{text[:30]}... ({len(text)} characters)"


def human_ns(ns: int) -> str:
    """A duration in ns as the shortest exact text in one unit (`1500ms`, `2h`)."""
    for unit in ("w", "d", "h", "m", "s", "ms", "us"):
        if ns % UNIT_NS[unit] == 0:
            return f"{ns // UNIT_NS[unit]}{unit}"
    return f"{ns}ns"


def iso_ns(ns: int) -> str:
    """A time in ns as ISO 8601 UTC with as many fraction digits as it needs."""
    seconds, fraction = divmod(ns, 1_000_000_000)
    text = datetime.fromtimestamp(seconds, UTC).strftime("%Y-%m-%dT%H:%M:%S")
    return text + (f".{fraction:09d}".rstrip("0") if fraction else "") + "Z"
