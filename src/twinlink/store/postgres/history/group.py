"""Group commit for PostgreSQL history: the batches that wait go in together, one transaction.

Appends are queued; one task per node takes what waits (at most MAX_BATCHES batches or
MAX_VALUES values) and writes it in one transaction of a few statements whatever the number
of batches: the series rows of all of them locked in id order (one statement), their
(device, seq) recorded in `ingested` (one INSERT, in key order; a (device, seq) stored before,
or twice in the group, is a duplicate: that append returns False), batch ids in queue order,
one COPY of all samples, and the summaries and latest values pre-aggregated per series (an
UPDATE ... FROM unnest applies one row per target row only). Each waiting append gets its
answer once that commit is done: the ack still follows a durable commit, as
docs/decisions/0013 needs, but a thousand batches wait for one WAL flush, not a thousand.
While a group commits, the next one forms.

Partitions, and the streams and series not yet cached, are made before, in short
transactions of their own (one stream each, as writer.py does; a series made for a batch
whose group then fails stays, empty, as one made for a resent batch does). A batch that
would give its stream too many signals is refused there, alone, before anything of it is
written. A group whose transaction fails for a reason tied to one of its batches (a
partition dropped meanwhile by another node's retention, series ids another node deleted,
text PostgreSQL cannot hold) is written again one batch at a time (writer.py), so each batch
gets its own outcome; the database away (StorageError) fails every append of the group, and
the devices send again.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import asyncpg
import orjson

from twinlink.domain.errors import StorageError, TooManySignalsError, TwinlinkError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.postgres.db import Connection
from twinlink.store.postgres.history import partitions
from twinlink.store.postgres.history.writer import (
    COLUMNS,
    Column,
    HistoryWriter,
    StreamKey,
    columns,
    kind_of,
    lock,
    make_series,
    records,
    stream_series,
    typed,
)

log = logging.getLogger("twinlink.store")

MAX_BATCHES = 256  # a group's batches at most
MAX_VALUES = 200_000  # and its values (a larger batch goes alone)
STOPPED = (
    "The server stopped before this batch's transaction ended: it may not have been stored. "
    "Send it again (a batch stored before is not stored twice)."
)


@dataclass(slots=True, eq=False)
class _Item:
    batch: SampleBatch
    device_id: int | None
    future: asyncio.Future[bool]
    size: int  # values
    by_signal: dict[str, Column] = field(default_factory=dict)
    stream_id: int = 0
    ids: dict[str, int] = field(default_factory=dict)  # series id by signal


class _Stale(Exception):
    """Some cached series ids of the group are gone (another node deleted their history).
    Control flow inside the writer, outside the error family: the group is written again
    one batch at a time, and no caller ever sees it."""


@dataclass(slots=True)
class _Series:
    """What a group adds to one series: its summary and its newest value."""

    n: int
    first_t: int
    last_t: int
    kinds: str
    newest: tuple[int, int]  # (time, batch id): the later wins
    value: Value

    def add(self, times: list[int], kind: str, newest: tuple[int, int], value: Value) -> None:
        """A later batch's values of the series."""
        self.n += len(times)
        self.first_t = min(self.first_t, min(times))
        self.last_t = max(self.last_t, newest[0])
        if kind not in self.kinds:
            self.kinds += kind
        if newest >= self.newest:  # as the upsert of latest: a later equal time wins
            self.newest, self.value = newest, value


class GroupCommit:
    def __init__(self, writer: HistoryWriter) -> None:
        self.writer = writer
        self._queue: deque[_Item] = deque()
        self._task: asyncio.Task[None] | None = None
        self.groups = 0  # transactions written, each of one or more batches
        self.grouped = 0  # batches they held
        self.fallbacks = 0  # groups written again one batch at a time

    async def append(self, batch: SampleBatch, device_id: int | None) -> bool:
        """True once the batch is committed, False when its (device, seq) was stored before."""
        if not batch.times:
            return True
        future: asyncio.Future[bool] = asyncio.get_running_loop().create_future()
        self._queue.append(_Item(batch, device_id, future, sum(map(len, batch.values))))
        if self._task is None:
            self._task = asyncio.create_task(self._run(), name="history-group-commit")
        return await future

    async def close(self) -> None:
        """Wait for the appends queued (each caller gets its answer)."""
        if self._task is not None:
            with contextlib.suppress(Exception):
                await self._task

    async def _run(self) -> None:
        group: list[_Item] = []
        try:
            while self._queue:
                group = self._take()
                if group:
                    await self._write(group)
        finally:
            self._task = None
            for item in (*group, *self._queue):  # cancelled: the node is stopping
                _settle(item, error=StorageError(STOPPED))
            self._queue.clear()

    def _take(self) -> list[_Item]:
        """The next group: the oldest waiting batches, within the bounds. A batch whose
        caller went away is dropped: nobody was answered, its device sends it again."""
        group: list[_Item] = []
        values = 0
        while self._queue and len(group) < MAX_BATCHES:
            item = self._queue[0]
            if group and values + item.size > MAX_VALUES:
                break
            self._queue.popleft()
            if not item.future.done():
                group.append(item)
                values += item.size
        return group

    async def _write(self, group: list[_Item]) -> None:
        try:
            async with self.writer.db.connection() as conn:
                todo = await self._prepare(conn, group)
                stored = await _commit(conn, todo) if todo else []
        except StorageError as err:  # the database away: every caller answers 503
            for item in group:
                _settle(item, error=err)
            return
        except Exception as err:  # tied to a batch (_Stale, CheckViolationError, ...)
            await self._one_by_one(group, err)
            return
        self.groups += 1
        self.grouped += len(todo)
        for item, result in zip(todo, stored, strict=True):
            _settle(item, result)

    async def _one_by_one(self, group: list[_Item], err: Exception) -> None:
        """The group's transaction failed for one of its batches: write each alone, as
        writer.py does, so that one fails and the others are stored."""
        self.fallbacks += 1
        # anything but these is a bug of the group's own: said loud, or every group would
        # quietly go batch by batch
        expected = isinstance(err, (_Stale, asyncpg.CheckViolationError, TwinlinkError))
        log.log(
            logging.INFO if expected else logging.WARNING,
            "a group of %d batches is written one at a time: %r", len(group), err,
            extra={"event": "history_group_split", "batches": len(group)},
            exc_info=not expected,
        )  # fmt: skip
        if isinstance(err, asyncpg.CheckViolationError):
            self.writer.partitions.clear()  # one was dropped since we made it
        for item in group:
            if item.future.done():  # refused, or its caller went away
                continue
            try:
                _settle(item, await self.writer.append(item.batch, item.device_id))
            except Exception as failed:  # its own outcome, raised to its own caller
                _settle(item, error=failed)

    async def _prepare(self, conn: Connection, group: list[_Item]) -> list[_Item]:
        """Make the partitions and series the group needs, each in a transaction of its
        own; refuse the batches that would give their stream too many signals. The batches
        left to write, in queue order."""
        writer = self.writer
        needed: set[int] = set()
        streams: dict[StreamKey, list[_Item]] = {}
        for item in group:
            item.by_signal = columns(item.batch)
            needed |= partitions.keys_of(item.batch.times)
            streams.setdefault((item.batch.twin_id, item.batch.stream), []).append(item)
        needed -= writer.partitions
        for number in sorted(needed):
            await partitions.create(conn, number)
        writer.partitions |= needed
        for key, items in streams.items():
            cached = writer.series.get(key)
            if cached is None or any(s not in cached[1] for i in items for s in i.by_signal):
                cached = await self._make_series(conn, key, items)
            for item in items:
                item.stream_id, item.ids = cached
        return [item for item in group if not item.future.done()]

    async def _make_series(
        self, conn: Connection, key: StreamKey, items: list[_Item]
    ) -> tuple[int, dict[str, int]]:
        """The stream's series, made for the new signals of its batches; the limit counted
        batch after batch, in queue order, as when they are written one by one."""
        async with conn.transaction():
            stream_id, ids = await stream_series(conn, key)
            new: dict[str, None] = {}
            for item in items:
                fresh = [s for s in item.by_signal if s not in ids and s not in new]
                if not fresh:
                    continue
                try:
                    self.writer.check_limit(item.batch, len(ids) + len(new) + len(fresh), fresh)
                except TooManySignalsError as err:
                    _settle(item, error=err)
                    continue
                new.update(dict.fromkeys(fresh))
            if new:
                ids.update(await make_series(conn, stream_id, list(new)))
        self.writer.series[key] = (stream_id, ids)
        return stream_id, ids


async def _commit(conn: Connection, todo: list[_Item]) -> list[bool]:
    """Write the batches in one transaction; for each, whether it was stored (False: its
    (device, seq) was stored before). _Stale when some series ids are gone."""
    series_ids = sorted({sid for item in todo for sid in item.ids.values()})
    async with conn.transaction():
        if not await lock(conn, series_ids):
            raise _Stale("some cached series ids are gone (their history was deleted)")
        stored = await _ingest(conn, todo)
        kept = [item for item, ok in zip(todo, stored, strict=True) if ok]
        if kept:
            await _write(conn, kept)
    return stored


async def _ingest(conn: Connection, todo: list[_Item]) -> list[bool]:
    """Record the batches' (device, seq), in key order (nodes storing the same ones wait on
    each other in one order, never in a circle). A key found stored, or already taken by an
    earlier batch of the group, is a duplicate."""
    stored = [True] * len(todo)
    first: dict[tuple[int, int], int] = {}
    at: list[int] = []
    for i, item in enumerate(todo):
        seq = item.batch.seq
        if item.device_id is None or seq is None:
            continue
        if (item.device_id, seq) in first:
            stored[i] = False
            continue
        first[(item.device_id, seq)] = i
        at.append(item.batch.received_ns)
    if first:
        devices, seqs = zip(*first, strict=True)
        rows = await conn.fetch(_INGESTED, list(devices), list(seqs), at)
        new = {(r[0], r[1]) for r in rows}
        for key, i in first.items():
            stored[i] = key in new
    return stored


async def _write(conn: Connection, kept: list[_Item]) -> None:
    """The samples of the batches (one COPY), the series' summaries and latest values."""
    rows = await conn.fetch("SELECT nextval('batch_ids') FROM generate_series(1, $1)", len(kept))
    batch_ids = sorted(r[0] for r in rows)  # in queue order: equal times keep arrival order
    parts: list[Iterator[tuple[Any, ...]]] = []
    by_series: dict[int, _Series] = {}
    for item, batch_id in zip(kept, batch_ids, strict=True):
        for signal, column in item.by_signal.items():
            kind = kind_of(column.values)
            values = typed(kind, column.values)
            sid = item.ids[signal]
            parts.append(records(item.stream_id, sid, batch_id, kind, column, values))
            # the newest: the largest time, of equal times the last in the batch
            last = max(range(len(column.times)), key=lambda i: (column.times[i], i))
            last_t = column.times[last]
            value = column.values[last] if kind != "f" else values[last]
            seen = by_series.get(sid)
            if seen is None:
                first_t = min(column.times)
                by_series[sid] = _Series(
                    len(column.times), first_t, last_t, kind, (last_t, batch_id), value
                )
            else:
                seen.add(column.times, kind, (last_t, batch_id), value)
    await conn.copy_records_to_table(
        "samples", records=(r for part in parts for r in part), columns=COLUMNS
    )
    sids = list(by_series)
    summaries = by_series.values()
    await conn.execute(
        _SUMMARY, sids, [s.n for s in summaries], [s.first_t for s in summaries],
        [s.last_t for s in summaries], [s.kinds for s in summaries],
    )  # fmt: skip
    await conn.execute(
        _LATEST, sids, [s.newest[0] for s in summaries], [s.newest[1] for s in summaries],
        [orjson.dumps(s.value).decode() for s in summaries],
    )  # fmt: skip


def _settle(item: _Item, result: bool = False, error: BaseException | None = None) -> None:
    """Answer the batch's caller, unless it went away (or was answered)."""
    if item.future.done():
        return
    if error is not None:
        item.future.set_exception(error)
    else:
        item.future.set_result(result)


_INGESTED = (
    "INSERT INTO ingested (device_id, seq, at_ns, published) "
    "SELECT d, s, a, false FROM unnest($1::bigint[], $2::bigint[], $3::bigint[]) AS u(d, s, a) "
    "ORDER BY d, s ON CONFLICT DO NOTHING RETURNING device_id, seq"
)
# kinds: those of the group's values, in order of appearance; the ones the series lacks are
# added in that order, as batch after batch would
_SUMMARY = (
    "UPDATE series s SET n = s.n + u.n, first_t = LEAST(s.first_t, u.first_t), "
    "last_t = GREATEST(s.last_t, u.last_t), kinds = s.kinds || coalesce(("
    "SELECT string_agg(k, '' ORDER BY o) FROM unnest(string_to_array(u.kinds, NULL)) "
    "WITH ORDINALITY AS x(k, o) WHERE strpos(s.kinds, k) = 0), '') "
    "FROM unnest($1::bigint[], $2::bigint[], $3::bigint[], $4::bigint[], $5::text[]) "
    "AS u(id, n, first_t, last_t, kinds) WHERE s.id = u.id"
)
_LATEST = (
    "INSERT INTO latest (series_id, t, batch, value) "
    "SELECT * FROM unnest($1::bigint[], $2::bigint[], $3::bigint[], $4::text[]) "
    "ON CONFLICT (series_id) DO UPDATE SET t = excluded.t, batch = excluded.batch, "
    "value = excluded.value WHERE excluded.t >= latest.t"
)
