"""Which series a read is about: a twin's stream and its signals, looked up by name."""

from __future__ import annotations

from dataclasses import dataclass

from twinlink.domain.errors import NotFoundError
from twinlink.store.postgres.db import Connection

_KIND_NAMES = {"i": "integer", "f": "number", "b": "bool", "j": "string"}


@dataclass(frozen=True, slots=True)
class Series:
    id: int
    signal: str
    kinds: str  # some of i, f, b, j


@dataclass(frozen=True, slots=True)
class Selection:
    """A stream and the series asked for, in the order asked."""

    stream_id: int
    series: list[Series]

    @property
    def ids(self) -> list[int]:
        return [s.id for s in self.series]

    @property
    def names(self) -> list[str]:
        return [s.signal for s in self.series]


def kind_name(kinds: str) -> str:
    """The kind of a signal from the kinds of its values (as the SQLite backend names it)."""
    if len(kinds) == 1:
        return _KIND_NAMES[kinds]
    return "number" if set(kinds) <= {"i", "f"} else "mixed"


async def select_series(
    conn: Connection, twin_id: int, stream: str, signals: list[str] | None
) -> Selection:
    """The series of `signals` (every signal when None) of one stream. NotFoundError names
    what exists when the stream or a signal does not. As in the SQLite backend, a signal
    whose samples retention deleted is still known (its reads are empty)."""
    rows = await conn.fetch(
        "SELECT st.id, se.id, se.signal, se.kinds FROM streams st JOIN series se "
        "ON se.stream_id = st.id WHERE st.twin_id = $1 AND st.name = $2 "
        "ORDER BY se.signal",
        twin_id, stream,
    )  # fmt: skip
    known = {row[2]: Series(row[1], row[2], row[3]) for row in rows}
    if not known:
        names = await conn.fetch(
            "SELECT DISTINCT st.name FROM streams st JOIN series se ON se.stream_id = st.id "
            "WHERE st.twin_id = $1 ORDER BY st.name",
            twin_id,
        )
        have = (
            f"its streams: {', '.join(r[0] for r in names)}" if names else "it has no history yet"
        )
        raise NotFoundError(f"no stream {stream!r} in this twin's history ({have})")
    stream_id = rows[0][0]
    if signals is None:
        return Selection(stream_id, list(known.values()))
    missing = [s for s in signals if s not in known]
    if missing:
        raise NotFoundError(
            f"stream {stream!r} has no signal {_some(list(map(repr, missing)))} "
            f"(its signals: {_some(list(known))})"
        )
    return Selection(stream_id, [known[s] for s in dict.fromkeys(signals)])


def _some(names: list[str], most: int = 20) -> str:
    """Names for a message: a stream may have thousands of signals, a message shows 20."""
    if len(names) <= most:
        return ", ".join(names)
    return f"{', '.join(names[:most])} and {len(names) - most} more"
