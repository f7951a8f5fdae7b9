"""What a group commit writes, on the writer's thread: batches as blocks (or staged rows),
staged rows moved into blocks, merged small blocks, and the latest values; with the writer's
memory of the series table (series_cache.py). The group commit around it is writer.py."""

from __future__ import annotations

import sqlite3

import orjson

from twinlink.domain.errors import TooManySignalsError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.store.sqlite.history import staging
from twinlink.store.sqlite.history.codec import INSERT_BLOCK, block_row, encode, split_signals
from twinlink.store.sqlite.history.compact import SMALL, Compacted, compact_series
from twinlink.store.sqlite.history.series_cache import Entry, Key, SeriesCache

# Distinct signals a stream may have (TWINLINK_MAX_SIGNALS_PER_STREAM): far above any real
# device's, low enough that a device sending a new name with every sample by mistake is
# stopped before its stream is too wide to read back in one piece.
MAX_SIGNALS_PER_STREAM = 1_000


class BlockWriter:
    def __init__(self, max_signals_per_stream: int = MAX_SIGNALS_PER_STREAM) -> None:
        self.max_signals_per_stream = max_signals_per_stream
        self.cache = SeriesCache()

    def load(self, conn: sqlite3.Connection) -> None:
        """Read what the cache holds from the file (at open)."""
        self.cache.load(
            conn.execute("SELECT id, twin_id, stream, signal, max_span_ns FROM series"),
            staging.counts(conn),  # rows a crash left staged: moved soon after open
        )

    def store(
        self,
        conn: sqlite3.Connection,
        batch: SampleBatch,
        device_id: int | None,
        ends: list[tuple[int, int, Value]],
    ) -> bool:
        """Store one batch (inside the writer's savepoint for it): False when this device's
        `seq` was stored before. The (series, last time, last value) of its blocks go to
        `ends`, for the latest values; a staged batch has none yet."""
        if device_id is not None and batch.seq is not None:
            cursor = conn.execute(
                "INSERT OR IGNORE INTO ingested (device_id, seq, at_ns) VALUES (?, ?, ?)",
                (device_id, batch.seq, batch.received_ns),
            )
            if cursor.rowcount == 0:
                return False
        columns = split_signals(batch.times, batch.values)
        get = self.cache.get
        known = [get((batch.twin_id, batch.stream, signal)) for signal in columns]
        if None in known:
            self._check_signals(
                batch, [s for s, k in zip(columns, known, strict=True) if k is None]
            )
        if len(batch.times) < staging.STAGE_BELOW:  # one row now, blocks later (staging.py)
            staged: list[staging.Column] = []
            for (signal, (times, values)), entry in zip(columns.items(), known, strict=True):
                key = (batch.twin_id, batch.stream, signal)
                span = max(times) - min(times)
                staged.append((self._series_id(conn, key, entry, span), signal, times, values))
            conn.execute(
                staging.INSERT_STAGED, staging.staged_row(batch.twin_id, batch.stream, staged)
            )
            self.cache.note_staged(batch.twin_id, 1)
            return True
        if self.cache.staged_now(batch.twin_id):
            # Blocks are read in the order they were written (equal times in arrival
            # order): the twin's staged batches, which came first, go first.
            while self.flush_staged(conn, twin_id=batch.twin_id):
                pass
            known = [get((batch.twin_id, batch.stream, signal)) for signal in columns]
        rows = []
        for (signal, (times, values)), entry in zip(columns.items(), known, strict=True):
            block = encode(signal, times, values)
            key = (batch.twin_id, batch.stream, signal)
            series_id = self._series_id(conn, key, entry, block.t1 - block.t0)
            rows.append(block_row(series_id, block))
            ends.append((series_id, block.t1, block.last_v))
            if block.n < SMALL:
                self.cache.note_small(series_id)
        conn.executemany(INSERT_BLOCK, rows)
        return True

    def _check_signals(self, batch: SampleBatch, new: list[str]) -> None:
        """Refuse the whole batch when its `new` signals would give its stream too many."""
        twin_id, stream = batch.twin_id, batch.stream
        total = self.cache.signals(twin_id, stream) + len(new)
        limit = self.max_signals_per_stream
        if total <= limit:
            return
        named = ", ".join(repr(s) for s in new[:3]) + (
            f" and {len(new) - 3} more" if len(new) > 3 else ""
        )
        raise TooManySignalsError(
            f"this batch would give stream {stream!r} of twin {batch.twin!r} {total} signals "
            f"(new: {named}); a stream may have at most {limit} "
            "(the server's TWINLINK_MAX_SIGNALS_PER_STREAM). The batch was not stored."
        )

    def _series_id(self, conn: sqlite3.Connection, key: Key, known: Entry | None, span: int) -> int:
        """The series of `key` (`known`: its cached entry), made or widened for a block that
        spans `span` ns."""
        if known is None:
            cursor = conn.execute(
                "INSERT INTO series (twin_id, stream, signal, max_span_ns) VALUES (?, ?, ?, ?)",
                (*key, span),
            )
            assert cursor.lastrowid is not None
            self.cache.add(key, cursor.lastrowid, span)
            return cursor.lastrowid
        series_id, max_span = known
        if span > max_span:
            conn.execute("UPDATE series SET max_span_ns = ? WHERE id = ?", (span, series_id))
            self.cache.widen(key, series_id, span)
        return series_id

    @staticmethod
    def write_latest(conn: sqlite3.Connection, latest: dict[int, tuple[int, Value]]) -> None:
        conn.executemany(
            "INSERT INTO latest (series_id, t, value) VALUES (?, ?, ?) "
            "ON CONFLICT (series_id) DO UPDATE SET t = excluded.t, value = excluded.value "
            "WHERE excluded.t >= latest.t",
            [(sid, t, orjson.dumps(v).decode()) for sid, (t, v) in latest.items()],
        )

    def compact(self, conn: sqlite3.Connection, series_id: int, budget: int = 10**18) -> Compacted:
        """Merge the series' small blocks, up to `budget` samples (compact.py); keeps the
        cached span in step."""
        done = compact_series(conn, series_id, budget)
        if done.max_span_ns:
            row = conn.execute(
                "SELECT twin_id, stream, signal, max_span_ns FROM series WHERE id = ?",
                (series_id,),
            ).fetchone()
            if row is not None:
                self.cache.widen((row[0], row[1], row[2]), series_id, row[3])
        return done

    def take_small_blocks(self) -> set[int]:
        """The series that got small blocks (committed) since the last call."""
        return self.cache.take_small()

    def forget_series(self, conn: sqlite3.Connection, twin_id: int) -> None:
        """Drop cached ids of a twin whose series were deleted, and its staged batches."""
        self.cache.note_staged(twin_id, -staging.delete_twin(conn, twin_id))
        self.cache.forget_twin(twin_id)

    def flush_staged(
        self, conn: sqlite3.Connection, twin_id: int | None = None,
        limit: int = staging.FLUSH_ROUND_ROWS,
    ) -> int:  # fmt: skip
        """Move staged rows into blocks, a block per signal (a `write` fn): the oldest `limit`
        rows of one twin, or every row of twins that hold about `limit`; the number moved."""
        twins = [twin_id] if twin_id is not None else self.cache.staged_twins(limit)
        if not twins:
            return 0
        found = staging.gather(conn, twins, limit)
        if not found.rowids:
            return 0
        rows = []
        latest: dict[int, tuple[int, Value]] = {}
        wider: list[tuple[int, int]] = []  # (span, series id): one statement for them all
        for run in found.runs:
            entry = self.cache.get(run.key)
            if entry is None or entry[0] != run.series_id:
                continue  # the twin's history was deleted since: so are these samples
            block = encode(run.key[2], run.times, run.values)
            span = block.t1 - block.t0
            if span > entry[1]:
                wider.append((span, run.series_id))
                self.cache.widen(run.key, run.series_id, span)
            rows.append(block_row(run.series_id, block))
            known = latest.get(run.series_id)
            if known is None or block.t1 >= known[0]:
                latest[run.series_id] = (block.t1, block.last_v)
            if block.n < SMALL:
                self.cache.note_small(run.series_id)
        conn.executemany("UPDATE series SET max_span_ns = ? WHERE id = ?", wider)
        conn.executemany(INSERT_BLOCK, rows)
        self.write_latest(conn, latest)
        staging.delete_rows(conn, found.rowids)
        for twin, moved in found.twins.items():
            self.cache.note_staged(twin, -moved)
        return len(found.rowids)
