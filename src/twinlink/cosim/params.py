"""The settings a co-simulation is created or started with (name, mode, factor, twin's
prefix and stream), checked with errors that say what to send instead."""

from __future__ import annotations

import math
import re

from twinlink.domain.cosims import MODES
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.samples import STREAM_NAME

PREFIX = re.compile(r"^[A-Za-z_][A-Za-z0-9_.:-]{0,63}$")
MAX_FACTOR = 1e6
DEFAULT_NAME = "cosim"
DEFAULT_STREAM = "cosim"


def check_name(name: str | None) -> str:
    if name is None:
        return DEFAULT_NAME
    name = name.strip()
    if not 0 < len(name) <= 100 or not name.isprintable():
        raise InvalidInputError(f"name: {name!r} is not a name: 1 to 100 printable characters")
    return name


def check_mode(mode: str) -> str:
    if mode not in MODES:
        raise InvalidInputError(f"mode: {mode!r} is not a mode: batch or realtime")
    return mode


def check_factor(factor: float) -> float:
    if not (math.isfinite(factor) and 0 < factor <= MAX_FACTOR):
        raise InvalidInputError(
            f"factor: {factor!r} is not a real-time factor: a number above 0 and at most "
            f"{MAX_FACTOR:g} (1.0 = wall clock, 2.0 = twice as fast)"
        )
    return factor


def check_prefix(prefix: str) -> str:
    if prefix and not PREFIX.match(prefix):
        raise InvalidInputError(
            f"prefix: {prefix!r} cannot start a signal name: a letter or '_', then letters, "
            "digits, '_', '.', ':' or '-' (at most 64)"
        )
    return prefix


def check_stream(stream: str | None) -> str:
    if stream is None:
        return DEFAULT_STREAM
    if not STREAM_NAME.match(stream):
        raise InvalidInputError(
            f"stream: {stream!r} is not a stream name: a lower-case letter, then lower-case "
            "letters, digits, '_' or '-' (at most 64)"
        )
    return stream
