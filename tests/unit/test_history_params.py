"""Query parameters of the history API: times, durations, names, choices and cursors."""

from __future__ import annotations

from typing import Any

import pytest

from twinlink.history.params import (
    QueryError,
    format_cursor,
    human_ns,
    iso_ns,
    parse_choice,
    parse_choices,
    parse_cursor,
    parse_duration,
    parse_names,
    parse_time,
)

NOW = 1_732_200_000_123_456_789
T2024 = 1_704_067_200 * 10**9


@pytest.mark.parametrize(
    ("text", "ns"),
    [
        ("1s", 10**9),
        ("500ms", 5 * 10**8),
        ("1.5h", 5400 * 10**9),
        ("15m", 900 * 10**9),
        ("7d", 7 * 86_400 * 10**9),
        ("2w", 14 * 86_400 * 10**9),
        ("250us", 250_000),
        ("10ns", 10),
        (" 1 s ", 10**9),
    ],
)
def test_durations(text: str, ns: int) -> None:
    assert parse_duration(text, "bucket") == ns


@pytest.mark.parametrize("text", ["", "1", "s", "1sec", "-1s", "0s", "1e3s", "99999999w"])
def test_bad_durations_say_what_is_accepted(text: str) -> None:
    with pytest.raises(QueryError, match="`bucket`") as err:
        parse_duration(text, "bucket")
    assert "ms" in str(err.value) or "more than 0" in str(err.value)


@pytest.mark.parametrize(
    ("text", "ns"),
    [
        (None, -1),
        ("", -1),
        ("now", NOW),
        ("-1h", NOW - 3600 * 10**9),
        ("-90s", NOW - 90 * 10**9),
        (str(T2024), T2024),
        ("2024-01-01T00:00:00Z", T2024),
        ("2024-01-01T00:00:00", T2024),  # no zone: UTC
        ("2024-01-01", T2024),
        ("2024-01-01 00:00", T2024),
        ("2024-01-01T02:00:00+02:00", T2024),
        ("2024-01-01T00:00:00.5Z", T2024 + 5 * 10**8),
        ("2024-01-01T00:00:00.123456789Z", T2024 + 123_456_789),
        ("2023-12-31T23:59:59.999999999-00:00", T2024 - 1),
    ],
)
def test_times(text: str | None, ns: int) -> None:
    assert parse_time(text, "start", NOW, -1) == ns


@pytest.mark.parametrize(
    ("text", "hint"),
    [
        ("yesterday", "ISO 8601"),
        ("1732200000", "before 1973"),
        ("-5", "before 1973"),
        ("2024-13-01T00:00:00Z", "not a valid time"),
        ("2024-01-01T00:00:00.1234567891Z", "ISO 8601"),
        ("-1 fortnight", "duration"),
        ("99999999999999999999", "after 2262"),
        ("9999-12-31T00:00:00Z", "out of range"),
        ("0001-01-01", "out of range"),
    ],
)
def test_bad_times_say_what_is_accepted(text: str, hint: str) -> None:
    with pytest.raises(QueryError, match="`start`") as err:
        parse_time(text, "start", NOW, 0)
    assert hint in str(err.value)


def test_names_and_choices() -> None:
    assert parse_names(None) is None
    assert parse_names(" , ") is None
    assert parse_names("a, b.c,Input_F:1") == ["a", "b.c", "Input_F:1"]
    with pytest.raises(QueryError, match="'1a' is not a signal name"):
        parse_names("x,1a")
    assert parse_choices("max, avg,max", "fn", ("avg", "max"), ["avg"]) == ["max", "avg"]
    assert parse_choices(None, "fn", ("avg",), ["avg"]) == ["avg"]
    with pytest.raises(QueryError, match=r"`fn`: 'mean' not known; use one or more of avg, max"):
        parse_choices("mean", "fn", ("avg", "max"), ["avg"])
    assert parse_choice(None, "method", ("minmax", "lttb"), "minmax") == "minmax"
    with pytest.raises(QueryError, match="use one of minmax, lttb"):
        parse_choice("m4", "method", ("minmax", "lttb"), "minmax")


def test_cursors_round_trip() -> None:
    assert parse_cursor(format_cursor((T2024, 3))) == (T2024, 3)
    assert parse_cursor(None) is None
    for bad in ("abc", "12", "1.x", "1.-2", "99999999999999999999.0", "1.99999999999999999999"):
        with pytest.raises(QueryError, match="next_cursor"):
            parse_cursor(bad)


def test_human_durations_and_times() -> None:
    assert [human_ns(n) for n in (10**9, 90 * 10**9, 1500 * 10**6, 7, 3600 * 10**9)] == [
        "1s",
        "90s",
        "1500ms",
        "7ns",
        "1h",
    ]
    assert iso_ns(T2024) == "2024-01-01T00:00:00Z"
    assert iso_ns(T2024 + 120_000_000) == "2024-01-01T00:00:00.12Z"


@pytest.mark.parametrize(
    ("fn", "args"),
    [
        (parse_time, ("9" * 5000, "start", 0, 0)),
        (parse_time, ("²", "start", 0, 0)),
        (parse_duration, ("1" * 400 + ".5s", "bucket")),
        (parse_duration, ("1" * 5000 + "s", "bucket")),
        (parse_cursor, ("9" * 5000 + ".1",)),
    ],
)
def test_absurd_numbers_are_refused_with_a_short_message(fn: Any, args: tuple[Any, ...]) -> None:
    with pytest.raises(QueryError) as err:
        fn(*args)
    assert len(str(err.value)) < 300
