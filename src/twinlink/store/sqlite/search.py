"""Full-text search over twins and features with SQLite FTS5.

One row per (twin, privacy part, feature); the twin's own fields form a row with no feature.
A query is one FTS expression per term; a twin is a hit when every term matches some row of
it the reader may see, so "crane CAD" finds the crane even though "crane" is in its name and
"CAD" in a feature's keywords.
"""

from __future__ import annotations

import html
import sqlite3
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

from twinlink.store.records import SearchResult, SearchRow, Visibility
from twinlink.store.sqlite.db import Database
from twinlink.store.sqlite.visibility import part_visible

# bm25 column weights: name, description, keywords, extra. A match in a name or keyword says
# more about what a feature holds than one in a long description.
_WEIGHTS = "10.0, 2.0, 6.0, 1.0"
_TWIN_ROW_BOOST = 1.5  # a term in the twin's own name/description outranks one in a feature
# Snippets are marked with private-use characters, then HTML-escaped, then the marks become
# <mark> tags: a document's own text can never inject markup into a search result.
_OPEN, _CLOSE = "\ue000", "\ue001"
_SNIPPET = f"snippet(search_fts, -1, '{_OPEN}', '{_CLOSE}', '…', 10)"


def _safe_snippet(text: str) -> str:
    return html.escape(text).replace(_OPEN, "<mark>").replace(_CLOSE, "</mark>")


def write_search_rows(c: sqlite3.Connection, twin_id: int, rows: list[SearchRow]) -> None:
    c.execute(
        "DELETE FROM search_fts WHERE rowid IN (SELECT id FROM search_rows WHERE twin_id = ?)",
        (twin_id,),
    )
    c.execute("DELETE FROM search_rows WHERE twin_id = ?", (twin_id,))
    for row in rows:
        row_id = c.execute(
            "INSERT INTO search_rows(twin_id, privacy, feature) VALUES (?, ?, ?)",
            (twin_id, row.privacy, row.feature),
        ).lastrowid
        c.execute(
            "INSERT INTO search_fts(rowid, name, description, keywords, extra)"
            " VALUES (?, ?, ?, ?, ?)",
            (row_id, row.name, row.description, " ".join(row.keywords), row.extra),
        )
        c.executemany(
            "INSERT INTO search_keywords(row_id, keyword) VALUES (?, ?)",
            [(row_id, k) for k in dict.fromkeys(row.keywords)],
        )


@dataclass(slots=True)
class _Twin:
    score: float = 0.0
    terms: set[int] = field(default_factory=set)
    rows: dict[int, tuple[str | None, str]] = field(
        default_factory=dict
    )  # rowid -> feature, privacy


class SearchTables:
    db: Database

    async def search(
        self,
        vis: Visibility,
        terms: list[str],
        *,
        keyword: str | None,
        limit: int,
        offset: int,
        facet_limit: int = 25,
    ) -> SearchResult:
        return await self.db.read(
            lambda c: _search(c, vis, terms, keyword, limit, offset, facet_limit)
        )


def _search(
    c: sqlite3.Connection,
    vis: Visibility,
    terms: list[str],
    keyword: str | None,
    limit: int,
    offset: int,
    facet_limit: int,
) -> SearchResult:
    visible, vis_args = part_visible(vis, "s.twin_id", "s.privacy")
    kw_sql, kw_args = "", []
    if keyword:
        kw_sql = (
            " AND s.twin_id IN (SELECT s2.twin_id FROM search_rows s2 JOIN search_keywords k"
            " ON k.row_id = s2.id WHERE k.keyword = ? AND "
            + part_visible(vis, "s2.twin_id", "s2.privacy")[0]
            + ")"
        )
        kw_args = [keyword, *part_visible(vis, "s2.twin_id", "s2.privacy")[1]]

    twins: dict[int, _Twin] = defaultdict(_Twin)
    if terms:
        for i, term in enumerate(terms):
            rows = c.execute(
                f"SELECT s.id, s.twin_id, s.feature, s.privacy, bm25(search_fts, {_WEIGHTS}) AS r"
                " FROM search_fts JOIN search_rows s ON s.id = search_fts.rowid"
                f" WHERE search_fts MATCH ? AND {visible}{kw_sql}",
                [term, *vis_args, *kw_args],
            ).fetchall()
            best: dict[int, float] = {}
            for row_id, twin_id, feature, privacy, rank in rows:
                score = -rank * (_TWIN_ROW_BOOST if feature is None else 1.0)
                best[twin_id] = max(best.get(twin_id, 0.0), score)
                twins[twin_id].rows[row_id] = (feature, privacy)
            for twin_id, score in best.items():
                twins[twin_id].score += score
                twins[twin_id].terms.add(i)
        matched = {t: v for t, v in twins.items() if len(v.terms) == len(terms)}
    else:
        rows = c.execute(
            f"SELECT DISTINCT s.twin_id FROM search_rows s WHERE {visible}{kw_sql}",
            [*vis_args, *kw_args],
        ).fetchall()
        matched = {r[0]: _Twin() for r in rows}

    names = _names(c, list(matched))
    order = sorted(matched, key=lambda t: (-matched[t].score, names[t][1].lower()))
    page = order[offset : offset + limit]
    snippets = _snippets(c, terms, [r for t in page for r in matched[t].rows])
    hits = []
    for twin_id in page:
        slug, name = names[twin_id]
        features: dict[str | None, dict[str, Any]] = {}
        for row_id, (feature, privacy) in matched[twin_id].rows.items():
            entry = features.setdefault(feature, {"feature": feature, "privacy": privacy})
            if row_id in snippets and "snippet" not in entry:
                entry["snippet"] = snippets[row_id]
        hits.append(
            {
                "slug": slug,
                "name": name,
                "score": round(matched[twin_id].score, 4),
                "matches": sorted(features.values(), key=lambda m: (m["feature"] is not None,)),
            }
        )
    return SearchResult(total=len(order), hits=hits, facets=_facets(c, vis, order, facet_limit))


def _names(c: sqlite3.Connection, twin_ids: list[int]) -> dict[int, tuple[str, str]]:
    out: dict[int, tuple[str, str]] = {}
    for chunk in _chunks(twin_ids):
        marks = ", ".join("?" * len(chunk))
        for row in c.execute(f"SELECT id, slug, name FROM twins WHERE id IN ({marks})", chunk):
            out[row[0]] = (row[1], row[2])
    return out


def _snippets(c: sqlite3.Connection, terms: list[str], row_ids: list[int]) -> dict[int, str]:
    if not terms or not row_ids:
        return {}
    out: dict[int, str] = {}
    expr = " OR ".join(f"({t})" for t in terms)
    for chunk in _chunks(row_ids):
        marks = ", ".join("?" * len(chunk))
        for row in c.execute(
            f"SELECT rowid, {_SNIPPET} FROM search_fts WHERE search_fts MATCH ?"
            f" AND rowid IN ({marks})",
            [expr, *chunk],
        ):
            out[row[0]] = _safe_snippet(row[1])
    return out


def _facets(
    c: sqlite3.Connection, vis: Visibility, twin_ids: list[int], limit: int
) -> list[tuple[str, int]]:
    if not twin_ids:
        return []
    visible, args = part_visible(vis, "s.twin_id", "s.privacy")
    counts: dict[str, int] = defaultdict(int)
    spelled: dict[str, str] = {}
    for chunk in _chunks(twin_ids):
        marks = ", ".join("?" * len(chunk))
        for kw, n in c.execute(
            "SELECT k.keyword, count(DISTINCT s.twin_id) FROM search_keywords k"
            f" JOIN search_rows s ON s.id = k.row_id WHERE s.twin_id IN ({marks}) AND {visible}"
            " GROUP BY k.keyword",
            [*chunk, *args],
        ):
            counts[kw.lower()] += n
            spelled.setdefault(kw.lower(), kw)
    ranked = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:limit]
    return [(spelled[k], n) for k, n in ranked]


def _chunks(items: list[int], size: int = 900) -> list[list[int]]:
    return [items[i : i + size] for i in range(0, len(items), size)] if items else []
