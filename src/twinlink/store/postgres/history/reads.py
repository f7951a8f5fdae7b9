"""The read side of PostgreSQL history: streams, latest values, extent and pages of rows.

Rows join on (time, occurrence) as in the SQLite backend (store/sqlite/history/merge.py): the
k-th sample of a signal at time t goes into the k-th row at t, a signal's samples at one time
in their order of arrival (batch, then place in the batch). A page reads only the times it
returns: first the next `limit + 2` distinct times from the index, then the samples at them.
"""

from __future__ import annotations

from typing import Any

import orjson

from twinlink.domain.history import SamplePage
from twinlink.store.postgres.db import Connection
from twinlink.store.postgres.history.series import Selection, kind_name

COUNT_LIMIT = 5_000_000  # values read at most to count the rows of one stream

_STREAMS = (
    "SELECT st.id, st.name, se.signal, se.n, se.first_t, se.last_t, se.kinds "
    "FROM streams st JOIN series se ON se.stream_id = st.id "
    "WHERE st.twin_id = $1 AND se.n > 0 ORDER BY st.name, se.signal"
)
# A time counts as many rows as the signal with the most samples at it.
_ROW_COUNT = (
    "SELECT coalesce(sum(m), 0) FROM (SELECT max(c) AS m FROM (SELECT t, count(*) AS c "
    "FROM samples WHERE stream_id = $1 GROUP BY t, series_id) per_signal GROUP BY t) per_time"
)


async def stream_summaries(conn: Connection, twin_id: int) -> list[dict[str, Any]]:
    """Per stream: name, samples (rows), values, first and last time, and its signals."""
    streams: dict[str, dict[str, Any]] = {}
    ids: dict[str, int] = {}
    for stream_id, name, signal, n, first, last, kinds in await conn.fetch(_STREAMS, twin_id):
        stream = streams.get(name)
        if stream is None:
            ids[name] = stream_id
            stream = streams[name] = {
                "name": name, "samples": 0, "values": 0, "count": 0, "first": first,
                "last": last, "signals": [],
            }  # fmt: skip
        stream["values"] += n
        stream["first"], stream["last"] = min(stream["first"], first), max(stream["last"], last)
        stream["signals"].append(
            {"name": signal, "kind": kind_name(kinds), "values": n, "count": n, "first": first,
             "last": last}
        )  # fmt: skip
    for name, stream in streams.items():
        stream["count"] = stream["values"]
        if len(stream["signals"]) == 1:
            stream["samples"] = stream["values"]
        elif stream["values"] > COUNT_LIMIT:
            stream["samples"] = None  # unknown rather than slow
        else:
            stream["samples"] = int(await conn.fetchval(_ROW_COUNT, ids[name]))
    return list(streams.values())


async def latest_values(conn: Connection, found: Selection) -> dict[str, dict[str, Any]]:
    rows = await conn.fetch(
        "SELECT series_id, t, value FROM latest WHERE series_id = ANY($1::bigint[])", found.ids
    )
    by_id = {sid: (t, value) for sid, t, value in rows}
    return {
        s.signal: {"time": by_id[s.id][0], "value": orjson.loads(by_id[s.id][1])}
        for s in found.series
        if s.id in by_id
    }


async def data_extent(conn: Connection, found: Selection) -> tuple[int, int] | None:
    row = await conn.fetchrow(
        "SELECT min(t), max(t) FROM samples WHERE stream_id = $1 AND series_id = ANY($2::bigint[])",
        found.stream_id, found.ids,
    )  # fmt: skip
    if row is None or row[0] is None:
        return None
    return int(row[0]), int(row[1])


_TIMES = (
    "SELECT DISTINCT t FROM samples WHERE stream_id = $1 AND series_id = ANY($2::bigint[]) "
    "AND t >= $3 AND t <= $4 ORDER BY t LIMIT $5"
)
_ROWS = (
    "SELECT t, occ, array_agg(series_id), array_agg(kind), array_agg(vi), array_agg(vf), "
    "array_agg(vb), array_agg(vj) FROM (SELECT t, series_id, kind, vi, vf, vb, vj, "
    "row_number() OVER (PARTITION BY series_id, t ORDER BY batch, pos) - 1 AS occ "
    "FROM samples WHERE stream_id = $1 AND series_id = ANY($2::bigint[]) "
    "AND t >= $3 AND t <= $4) s WHERE (t, occ) >= ($3, $5) "
    "GROUP BY t, occ ORDER BY t, occ LIMIT $6"
)


async def sample_page(
    conn: Connection,
    found: Selection,
    start: int,
    end: int,
    limit: int,
    after: tuple[int, int] | None,
) -> SamplePage:
    low, low_occ = (start, 0) if after is None or after[0] < start else after
    # limit + 2 times hold at least limit + 1 rows past the cursor (all but the first time
    # give one each): enough to fill the page and know the key of the next one.
    times = await conn.fetch(_TIMES, found.stream_id, found.ids, low, end, limit + 2)
    if not times:
        return SamplePage([], None)
    high = times[-1][0]
    rows = await conn.fetch(_ROWS, found.stream_id, found.ids, low, high, low_occ, limit + 1)
    order = {s.id: (i, s.signal) for i, s in enumerate(found.series)}
    page = [_row(order, row) for row in rows[:limit]]
    next_key = (rows[limit][0], rows[limit][1]) if len(rows) > limit else None
    return SamplePage(page, next_key)


_PICK = {"i": 0, "f": 1, "b": 2}  # of (vi, vf, vb)


def _row(order: dict[int, tuple[int, str]], row: Any) -> dict[str, Any]:
    t, _, ids, kinds, vi, vf, vb, vj = row
    cells = []
    for k, (sid, kind) in enumerate(zip(ids, kinds, strict=True)):
        value = orjson.loads(vj[k]) if kind == "j" else (vi, vf, vb)[_PICK[kind]][k]
        cells.append((*order[sid], value))
    cells.sort()
    return {"time": t, "values": {signal: value for _, signal, value in cells}}
