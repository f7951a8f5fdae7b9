"""Aggregates of PostgreSQL history in SQL: per signal and bucket of `width` ns aligned to
the epoch, count, sum, min, max, first and last, in one pass over the range's index entries
(memory: one row per bucket, however many samples). As in the SQLite backend: a signal
whose values in the range are all integers is aggregated exactly (`sum` a Python int however
large, `min`/`max`/`first`/`last` ints); any other numeric signal as floats (bools as 0 and
1); text values are left out (the numbers of a batch that mixed them with text count), and a
signal with only text is named in `text_only`.
"""

from __future__ import annotations

from typing import Any

from twinlink.domain.history import Aggregated
from twinlink.store.postgres.db import Connection
from twinlink.store.postgres.history.budget import ReadBudget
from twinlink.store.postgres.history.series import Selection

# a number: a numeric kind's value, or a number of a batch that mixed numbers with text
NUMERIC = "(kind <> 'j' OR vf IS NOT NULL)"
_RANGE = "stream_id = $1 AND series_id = ANY($2::bigint[]) AND t >= $3 AND t <= $4"
_CLASSIFY = (
    f"SELECT series_id, count(*) FILTER (WHERE {NUMERIC}), bool_and(kind = 'i') "
    f"FROM samples WHERE {_RANGE} GROUP BY series_id"
)
_NUMBER = "coalesce(vf, vi::float8, vb::int::float8)"
# floor(t / width) for negative times too (bigint division truncates toward zero)
_BUCKET = "(t / $5 - CASE WHEN t % $5 < 0 THEN 1 ELSE 0 END)"
_AGGREGATE = (
    f"SELECT series_id, {_BUCKET} AS b, count(*), sum(vi), sum({_NUMBER}), min(vi), max(vi), "
    f"min({_NUMBER}), max({_NUMBER}), min(ARRAY[t, batch, pos]), max(ARRAY[t, batch, pos]) "
    f"FROM samples WHERE {_RANGE} AND {NUMERIC} GROUP BY series_id, b ORDER BY b, series_id"
)
# the values at the first and last keys found (time, batch, place in the batch)
_VALUES = (
    f"SELECT k.series_id, k.t, k.batch, k.pos, s.vi, {_NUMBER} "
    "FROM unnest($2::bigint[], $3::bigint[], $4::bigint[], $5::bigint[]) "
    "AS k(series_id, t, batch, pos) JOIN samples s ON s.stream_id = $1 "
    "AND s.series_id = k.series_id AND s.t = k.t AND s.batch = k.batch AND s.pos = k.pos"
)


async def aggregate(
    conn: Connection,
    found: Selection,
    start: int,
    end: int,
    width: int,
    fns: list[str],
    budget: ReadBudget,
) -> Aggregated:
    kinds = {
        sid: (numbers, exact)
        for sid, numbers, exact in await conn.fetch(
            _CLASSIFY, found.stream_id, found.ids, start, end
        )
    }
    text = [s.signal for s in found.series if s.id in kinds and not kinds[s.id][0]]
    buckets = end // width - start // width + 1
    budget.values(sum(min(n, buckets) for n, _ in kinds.values()) * len(fns), "the aggregate")
    rows = await conn.fetch(_AGGREGATE, found.stream_id, found.ids, start, end, width)
    if not rows:
        return Aggregated([], text)
    ends = await _ends(conn, found.stream_id, rows)
    order = {s.id: (i, s.signal) for i, s in enumerate(found.series)}
    out: list[dict[str, Any]] = []
    for sid, bucket, count, isum, fsum, imin, imax, fmin, fmax, first, last in rows:
        exact = kinds[sid][1]
        first_v, last_v = ends[(sid, *first)], ends[(sid, *last)]
        total = int(isum) if exact else fsum
        stats = {
            "count": count, "sum": total, "avg": total / count,
            "min": imin if exact else fmin, "max": imax if exact else fmax,
            "first": first_v[0] if exact else first_v[1],
            "last": last_v[0] if exact else last_v[1],
        }  # fmt: skip
        if not out or out[-1]["time"] != bucket * width:
            out.append({"time": bucket * width, "values": {}})
        out[-1]["values"][order[sid]] = {fn: stats[fn] for fn in fns}
    for row in out:  # signals in the order asked
        row["values"] = {name: v for (_, name), v in sorted(row["values"].items())}
    return Aggregated(out, text)


async def _ends(
    conn: Connection, stream_id: int, rows: list[Any]
) -> dict[tuple[int, int, int, int], tuple[int | None, float]]:
    """{(series, time, batch, place): (int value, float value)} at each bucket's first and
    last key: one statement for them all."""
    keys = {(row[0], *row[9]) for row in rows} | {(row[0], *row[10]) for row in rows}
    ids, times, batches, places = (list(c) for c in zip(*keys, strict=True))
    found = await conn.fetch(_VALUES, stream_id, ids, times, batches, places)
    return {(sid, t, batch, pos): (vi, vf) for sid, t, batch, pos, vi, vf in found}
