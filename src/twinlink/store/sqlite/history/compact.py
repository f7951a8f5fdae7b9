"""Compaction: merge a series' small blocks into large ones, in the background.

A device that sends every 50 ms writes 72 000 blocks per signal and hour, and reading that many
rows alone would make an hour's plot slow. Runs of small neighbouring blocks (by time) are
merged into blocks of up to `MAX_SAMPLES` samples spanning at most `MAX_SPAN_NS`; the merged
block carries the same summary as one written whole, so readers cannot tell the difference.
Each call handles one series inside the writer's group commit, so ingest waits at most for
one series' merge.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any

from twinlink.domain.samples import Value
from twinlink.store.sqlite.history.codec import (
    INSERT_BLOCK,
    block_row,
    decode_times,
    decode_values,
    encode,
)

MAX_SAMPLES = 10_000
MAX_SPAN_NS = 60 * 10**9
SMALL = MAX_SAMPLES // 4  # blocks at least this big are left alone
MIN_RUN = 4  # neighbours merged only when it makes at least this many rows one


@dataclass(slots=True)
class Compacted:
    blocks_before: int = 0
    blocks_after: int = 0
    max_span_ns: int = 0
    samples: int = 0  # in the blocks merged
    more: bool = False  # runs left for another call (the budget was spent)


def plan_runs(
    blocks: list[tuple[int, int, int, int]], max_samples: int = MAX_SAMPLES
) -> list[list[int]]:
    """Group (rowid, t0, t1, n) rows, sorted by t0, into runs of neighbours to merge: each run
    holds at most `max_samples` samples and `MAX_SPAN_NS` of time, and only runs of two or more
    blocks are returned. A big block ends the current run (it is not merged)."""
    runs: list[list[int]] = []
    run: list[int] = []
    count = start = 0
    for rowid, t0, t1, n in blocks:
        fits = run and count + n <= max_samples and t1 - start <= MAX_SPAN_NS
        if n >= SMALL or not fits:
            if len(run) > 1:
                runs.append(run)
            run, count, start = [], 0, t0
            if n >= SMALL:
                continue
        if not run:
            start = t0
        run.append(rowid)
        count += n
    if len(run) > 1:
        runs.append(run)
    return runs


def compact_series(conn: sqlite3.Connection, series_id: int, budget: int = 10**18) -> Compacted:
    """Merge the runs of small blocks of one series (call inside a write transaction); runs
    of fewer than MIN_RUN blocks are left as they are (a slow device's staged blocks, one
    every half minute, are worth little merging). Stops once `budget` samples were merged,
    with `more` set when runs are left."""
    rows = conn.execute(
        "SELECT rowid, t0, t1, n FROM blocks WHERE series_id = ? ORDER BY t0, rowid",
        (series_id,),
    ).fetchall()
    done = Compacted()
    signal = ""
    for run in plan_runs(rows):
        if len(run) < MIN_RUN:
            continue
        if done.samples >= budget:
            done.more = True
            break
        times, values = _read_run(conn, run)
        block = encode(signal, times, values)
        conn.execute(
            f"DELETE FROM blocks WHERE rowid IN ({','.join('?' * len(run))})",
            run,
        )
        conn.execute(INSERT_BLOCK, block_row(series_id, block))
        done.blocks_before += len(run)
        done.blocks_after += 1
        done.samples += block.n
        done.max_span_ns = max(done.max_span_ns, block.t1 - block.t0)
    if done.max_span_ns:
        conn.execute(
            "UPDATE series SET max_span_ns = MAX(max_span_ns, ?) WHERE id = ?",
            (done.max_span_ns, series_id),
        )
    return done


def _read_run(conn: sqlite3.Connection, rowids: list[int]) -> tuple[list[int], list[Value]]:
    placeholders = ",".join("?" * len(rowids))
    found = {
        row[0]: row[1:]
        for row in conn.execute(
            f"SELECT rowid, kind, times, vals FROM blocks WHERE rowid IN ({placeholders})",
            rowids,
        )
    }
    # In the run's order, so samples with equal times keep their arrival order.
    blocks = [found[rowid] for rowid in rowids]
    kinds = {kind for kind, _, _ in blocks}
    if len(kinds) == 1 and "j" not in kinds:  # the usual case: one decode for the whole run
        kind = kinds.pop()
        times_blob = b"".join(b[1] for b in blocks)
        values_blob = b"".join(b[2] for b in blocks)
        return decode_times(times_blob).tolist(), decode_values(kind, values_blob).tolist()
    times: list[int] = []
    values: list[Any] = []
    for kind, time_blob, value_blob in blocks:
        times.extend(decode_times(time_blob).tolist())
        values.extend(decode_values(kind, value_blob).tolist())
    return times, values
