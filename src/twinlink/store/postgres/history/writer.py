"""The write side of PostgreSQL history, one batch in one transaction, and what group
commit (group.py, which writes the batches that wait together) shares with it: the rows a
batch becomes, the series and their limit, the lock order. group.py writes a group again
batch by batch here when one of its batches failed the group's transaction.

In that transaction: the rows of the batch's series are locked (in id order, so writers of
one stream on several nodes queue instead of deadlocking), the batch's (device, seq) is
recorded, as not yet published (a resent batch finds it there and writes nothing: `append`
returns False; published.py says whether it still has to go on the bus), its samples go
in with COPY (one row per value, typed by the kind of its signal in this batch), and the
summaries /streams shows and the latest values are brought up to date. The ack follows
the commit, so an acknowledged batch is durable in PostgreSQL; two nodes sending the
same (device, seq) at once store it once (the second waits for the first's commit, then
finds its row in `ingested`). Series ids are cached per node; when another node deleted the
twin's history meanwhile, the batch looks them up (makes them) again.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import repeat
from typing import Any

import asyncpg
import orjson

from twinlink.domain.errors import TooManySignalsError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.postgres.db import Connection, PostgresDatabase
from twinlink.store.postgres.history import partitions

MAX_SIGNALS_PER_STREAM = 1_000  # as the SQLite backend's (TWINLINK_MAX_SIGNALS_PER_STREAM)
COLUMNS = ("stream_id", "series_id", "t", "batch", "pos", "kind", "vi", "vf", "vb", "vj")
StreamKey = tuple[int, str]  # (twin id, stream)


class Column:
    """One signal's samples of a batch: times, positions in the batch, values."""

    __slots__ = ("pos", "times", "values")

    def __init__(self) -> None:
        self.times: list[int] = []
        self.pos: list[int] = []
        self.values: list[Value] = []


def columns(batch: SampleBatch) -> dict[str, Column]:
    found: dict[str, Column] = {}
    for pos, (t, row) in enumerate(zip(batch.times, batch.values, strict=True)):
        for signal, value in row.items():
            column = found.get(signal)
            if column is None:
                column = found[signal] = Column()
            column.times.append(t)
            column.pos.append(pos)
            column.values.append(value)
    return found


def kind_of(values: list[Value]) -> str:
    """As the SQLite backend's: ints, bools, numbers (ints mixed with floats), else JSON."""
    kinds = set(map(type, values))
    if kinds == {int}:
        return "i"
    if kinds == {bool}:
        return "b"
    if kinds <= {int, float}:
        return "f"
    return "j"


def typed(kind: str, values: list[Value]) -> list[Any]:
    """The values as stored in the column of `kind`."""
    if kind == "f":
        return [float(v) for v in values]
    if kind == "j":
        return [orjson.dumps(v).decode() for v in values]
    return values


def records(
    stream_id: int, series_id: int, batch_id: int, kind: str, column: Column, values: list[Any]
) -> Iterator[tuple[Any, ...]]:
    """The COPY rows of one signal of a batch, in the order of COLUMNS."""
    none = repeat(None)
    vi = values if kind == "i" else none
    vb = values if kind == "b" else none
    vj = values if kind == "j" else none
    if kind == "f":
        vf: Any = values
    elif kind == "j":  # the numbers (and bools) of a batch that mixed them with text count
        vf = [None if isinstance(v, str) else float(v) for v in column.values]
    else:
        vf = none
    return zip(
        repeat(stream_id), repeat(series_id), column.times, repeat(batch_id), column.pos,
        repeat(kind), vi, vf, vb, vj,
    )  # fmt: skip


class HistoryWriter:
    def __init__(self, db: PostgresDatabase, max_signals_per_stream: int) -> None:
        self.db = db
        self.max_signals_per_stream = max_signals_per_stream
        self.series: dict[StreamKey, tuple[int, dict[str, int]]] = {}  # ids, once committed
        self.partitions: set[int] = set()

    def forget(self, twin_id: int | None = None) -> None:
        """Drop what is cached (of one twin): its series were deleted."""
        if twin_id is None:
            self.series.clear()
            self.partitions.clear()
        else:
            self.series = {k: v for k, v in self.series.items() if k[0] != twin_id}

    async def append(self, batch: SampleBatch, device_id: int | None) -> bool:
        if not batch.times:
            return True
        try:
            stored = await self._append(batch, device_id)
        except asyncpg.CheckViolationError:
            # No partition for some time: one was dropped (retention) by another node since
            # we made it. Make it again, once.
            self.partitions.clear()
            stored = await self._append(batch, device_id)
        if stored is None:
            # The cached ids of the stream's series were deleted with the twin's history by
            # another node: look them up (make them) again, once.
            self.forget(batch.twin_id)
            stored = await self._append(batch, device_id)
        return bool(stored)

    async def _append(self, batch: SampleBatch, device_id: int | None) -> bool | None:
        """True when stored, False when stored before, None (nothing written) when the
        cached series ids are gone."""
        by_signal = columns(batch)
        needed = partitions.keys_of(batch.times) - self.partitions
        async with self.db.connection() as conn:
            for key in sorted(needed):
                await partitions.create(conn, key)
            self.partitions |= needed
            async with conn.transaction():
                stream_id, ids = await self._series(conn, batch, list(by_signal))
                if not await lock(conn, [ids[s] for s in by_signal]):
                    return None
                if device_id is not None and batch.seq is not None:
                    status = await conn.execute(
                        "INSERT INTO ingested (device_id, seq, at_ns, published) "
                        "VALUES ($1, $2, $3, false) ON CONFLICT DO NOTHING",
                        device_id, batch.seq, batch.received_ns,
                    )  # fmt: skip
                    if status.endswith(" 0"):
                        return False  # stored before
                await self._write(conn, stream_id, ids, by_signal)
        self.series[(batch.twin_id, batch.stream)] = (stream_id, ids)
        return True

    async def _write(
        self, conn: Connection, stream_id: int, ids: dict[str, int], by_signal: dict[str, Column]
    ) -> None:
        batch_id = await conn.fetchval("SELECT nextval('batch_ids')")
        rows: list[Iterator[tuple[Any, ...]]] = []
        summary: list[tuple[int, int, int, int, str]] = []
        latest: list[tuple[int, int, int, str]] = []
        for signal, column in by_signal.items():
            kind = kind_of(column.values)
            values = typed(kind, column.values)
            sid = ids[signal]
            rows.append(records(stream_id, sid, batch_id, kind, column, values))
            # the newest: the largest time, of equal times the last in the batch
            last = max(range(len(column.times)), key=lambda i: (column.times[i], i))
            first_t, last_t = min(column.times), column.times[last]
            summary.append((sid, len(column.times), first_t, last_t, kind))
            value = column.values[last] if kind != "f" else values[last]
            latest.append((sid, last_t, batch_id, orjson.dumps(value).decode()))
        await conn.copy_records_to_table(
            "samples", records=(r for part in rows for r in part), columns=COLUMNS
        )
        await conn.execute(_SUMMARY, *map(list, zip(*summary, strict=True)))
        await conn.execute(_LATEST, *map(list, zip(*latest, strict=True)))

    async def _series(
        self, conn: Connection, batch: SampleBatch, signals: list[str]
    ) -> tuple[int, dict[str, int]]:
        """The stream's id and its series' ids, made for new signals."""
        key = (batch.twin_id, batch.stream)
        cached = self.series.get(key)
        if cached is not None and all(s in cached[1] for s in signals):
            return cached
        stream_id, ids = await stream_series(conn, key)
        new = [s for s in signals if s not in ids]
        if new:
            self.check_limit(batch, len(ids) + len(new), new)
            ids.update(await make_series(conn, stream_id, new))
        return stream_id, ids

    def check_limit(self, batch: SampleBatch, total: int, new: list[str]) -> None:
        limit = self.max_signals_per_stream
        if total <= limit:
            return
        named = ", ".join(repr(s) for s in new[:3]) + (
            f" and {len(new) - 3} more" if len(new) > 3 else ""
        )
        raise TooManySignalsError(
            f"this batch would give stream {batch.stream!r} of twin {batch.twin!r} {total} "
            f"signals (new: {named}); a stream may have at most {limit} "
            "(the server's TWINLINK_MAX_SIGNALS_PER_STREAM). The batch was not stored."
        )


async def stream_series(conn: Connection, key: StreamKey) -> tuple[int, dict[str, int]]:
    """The stream's id (made when new) and the ids of the series it has."""
    stream_id = await conn.fetchval(
        "INSERT INTO streams (twin_id, name) VALUES ($1, $2) ON CONFLICT (twin_id, name) "
        "DO UPDATE SET name = excluded.name RETURNING id",
        *key,
    )
    rows = await conn.fetch("SELECT signal, id FROM series WHERE stream_id = $1", stream_id)
    return stream_id, {signal: sid for signal, sid in rows}


async def make_series(conn: Connection, stream_id: int, signals: list[str]) -> dict[str, int]:
    """The ids of new series of the stream (another node may make them at the same time)."""
    made = await conn.fetch(
        "INSERT INTO series (stream_id, signal) SELECT $1, unnest($2::text[]) "
        "ON CONFLICT (stream_id, signal) DO UPDATE SET signal = excluded.signal "
        "RETURNING signal, id",
        stream_id, signals,
    )  # fmt: skip
    return {signal: sid for signal, sid in made}


async def lock(conn: Connection, series_ids: list[int]) -> bool:
    """Lock the series' rows in id order: writers of one stream on several nodes then queue
    on them instead of locking them in different orders (a deadlock). False when some are
    gone (the twin's history was deleted since their ids were cached)."""
    locked = await conn.fetch(
        "SELECT id FROM series WHERE id = ANY($1::bigint[]) ORDER BY id FOR UPDATE",
        series_ids,
    )
    return len(locked) == len(series_ids)


_SUMMARY = (
    "UPDATE series s SET n = s.n + u.n, first_t = LEAST(s.first_t, u.first_t), "
    "last_t = GREATEST(s.last_t, u.last_t), "
    "kinds = CASE WHEN strpos(s.kinds, u.kind) > 0 THEN s.kinds ELSE s.kinds || u.kind END "
    "FROM unnest($1::bigint[], $2::bigint[], $3::bigint[], $4::bigint[], $5::text[]) "
    "AS u(id, n, first_t, last_t, kind) WHERE s.id = u.id"
)
_LATEST = (
    "INSERT INTO latest (series_id, t, batch, value) "
    "SELECT * FROM unnest($1::bigint[], $2::bigint[], $3::bigint[], $4::text[]) "
    "ON CONFLICT (series_id) DO UPDATE SET t = excluded.t, batch = excluded.batch, "
    "value = excluded.value WHERE excluded.t >= latest.t"
)
