"""JSON text read exactly, with one rule for integers everywhere.

orjson turns an integer above 2^64 into a float without a word, so a device's 2**80 or a
document's 20-digit id would be stored as a value nobody sent. msgspec keeps every integer
exact (and is as fast), so the reader decides: everything that stores or forwards a number
refuses integers outside 64 bits (int64) with `int64_problem`'s message, the same one YAML
documents, telemetry, properties and command arguments give.

`loads` is for every JSON the platform reads from outside (device batches, WebSocket and MQTT
messages, request bodies); `loads_document` adds what documents need: duplicate keys refused
with their line.
"""

from __future__ import annotations

import json
import re
from typing import Any

import msgspec

from twinlink.domain.errors import InvalidInputError

INT64_MIN = -(1 << 63)
INT64_MAX = (1 << 63) - 1
_DECODER = msgspec.json.Decoder()
_AT_BYTE = re.compile(r"\(byte (\d+)\)")


class JsonTextError(InvalidInputError):
    """JSON that cannot be read; `line` and `column` (1-based) say where, when known."""

    def __init__(self, message: str, line: int | None = None, column: int | None = None) -> None:
        where = f" (line {line}, column {column})" if line is not None else ""
        super().__init__(message + where)
        self.reason = message
        self.line = line
        self.column = column


def fits_int64(value: int) -> bool:
    return INT64_MIN <= value <= INT64_MAX


def show_int(value: int | str) -> str:
    """An integer as text, shortened in the middle when it is long."""
    text = value if isinstance(value, str) else _digits(value)
    if len(text) <= 40:
        return text
    digits = len(text.lstrip("-"))
    return f"{text[:12]}...{text[-6:]} ({digits} digits)"


def _digits(value: int) -> str:
    try:
        return str(value)
    except ValueError:  # over Python's int-to-text limit (4300 digits)
        return f"an integer of about {int(value.bit_length() * 0.30103)} digits"


def int64_problem(value: int | str) -> str:
    """The one message for an integer outside 64 bits."""
    return (
        f"{show_int(value)} does not fit in 64 bits (integers go from -2^63 to 2^63-1); "
        "send it as a string to keep every digit"
    )


def first_big_int(value: Any, path: str = "") -> tuple[str, int] | None:
    """(path, value) of the first integer outside 64 bits in nested lists and objects."""
    if type(value) is int:
        return None if fits_int64(value) else (path, value)
    if isinstance(value, dict):
        for key, item in value.items():
            found = first_big_int(item, f"{path}.{key}" if path else str(key))
            if found is not None:
                return found
    elif isinstance(value, list):
        for i, item in enumerate(value):
            found = first_big_int(item, f"{path}[{i}]")
            if found is not None:
                return found
    return None


def check_int64(value: Any, where: str = "") -> None:
    """Raise InvalidInputError when `value` holds an integer outside 64 bits."""
    found = first_big_int(value)
    if found is not None:
        path, number = found
        place = ": ".join(p for p in (where, path) if p)
        raise InvalidInputError(f"{place}: {int64_problem(number)}" if place else
                                int64_problem(number))  # fmt: skip


def _position(text: bytes, offset: int) -> tuple[int, int]:
    line = text.count(b"\n", 0, offset) + 1
    return line, offset - (text.rfind(b"\n", 0, offset) + 1) + 1


def loads(data: bytes | bytearray | memoryview | str) -> Any:
    """Parse JSON with integers kept exact (check them with `check_int64` or per value).
    Raises JsonTextError naming what is wrong and where."""
    raw = data.encode() if isinstance(data, str) else bytes(data)
    try:
        return _DECODER.decode(raw)
    except RecursionError as err:  # msgspec's own guard, at about 1 000 levels
        raise JsonTextError("the JSON text is nested too deeply (1 000 levels or more)") from err
    except msgspec.ValidationError as err:  # a number no type can hold
        text = str(err)
        if text.startswith("Integer value out of range"):
            raise JsonTextError(int64_problem(_longest_integer(raw))) from err
        raise JsonTextError("a number is out of range (beyond 1.8e308)") from err
    except msgspec.DecodeError as err:
        text = str(err)
        at = _AT_BYTE.search(text)
        reason = _AT_BYTE.sub("", text).strip().rstrip(":")
        if reason == "Input data was truncated":
            reason = "the JSON text ends too early (or holds an invalid \\u escape)"
        if at is None:
            raise JsonTextError(reason) from err
        raise JsonTextError(reason, *_position(raw, int(at.group(1)))) from err


def _longest_integer(raw: bytes) -> str:
    runs = re.findall(rb"-?\d+", raw)
    return max(runs, key=len).decode() if runs else "an integer"


_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]:]')


def _duplicate_key(text: str) -> tuple[str, int] | None:
    """The first key given twice in one object, and its offset, in JSON already known to be
    valid (so strings, brackets and colons are all the tokens that matter)."""
    objects: list[set[str] | None] = []  # per open bracket: its keys, None for an array
    last: re.Match[str] | None = None
    for token in _TOKEN.finditer(text):
        mark = token.group()
        if mark in "{[":
            objects.append(set() if mark == "{" else None)
        elif mark in "}]":
            objects.pop()
        elif mark == ":" and last is not None and objects and objects[-1] is not None:
            key = json.loads(last.group())
            if key in objects[-1]:
                return key, last.start()
            objects[-1].add(key)
        last = token if mark.startswith('"') else None
    return None


def loads_document(data: bytes | str) -> Any:
    """Parse a JSON document: as `loads`, and a key given twice in one object or an integer
    outside 64 bits is refused with its place, as YAML documents refuse them."""
    value = loads(data)  # syntax and number errors with their position, fast
    text = data.decode("utf-8") if isinstance(data, bytes) else data
    duplicate = _duplicate_key(text)
    if duplicate is not None:
        key, offset = duplicate
        line = text.count("\n", 0, offset) + 1
        column = offset - (text.rfind("\n", 0, offset) + 1) + 1
        raise JsonTextError(f"key {key!r} is given twice in one object", line, column)
    big = first_big_int(value)
    if big is not None:
        raise JsonTextError(f"{big[0] or 'the value'}: {int64_problem(big[1])}")
    return value
