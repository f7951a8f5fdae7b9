"""Full-text search over twins and features with SQLite FTS5 (tables: 0002_search.sql).

A twin is a hit when every word of the query matches one privacy part of it the reader may
see, so "crane CAD" finds the crane although "crane" is in its name and "CAD" in a feature's
keywords. Hits are ranked by bm25 over one document per part, with weights name 10, feature
names 6, keywords 5, descriptions 2, other text 1; the features that matched are then looked
up for the page of hits only.
"""

from __future__ import annotations

import sqlite3
from collections import Counter
from typing import Any

from twinlink.domain.merge import level_order
from twinlink.domain.records import SearchResult, SearchRow, Visibility
from twinlink.store.snippets import Highlighter
from twinlink.store.sqlite.db import Database
from twinlink.store.sqlite.visibility import part_visible, visible_private_parts

FACET_SAMPLE = 100  # facets count the best this many hits
RANK_LIMIT = 2000  # matching parts ranked in full by bm25; above, only name matches are
# Keywords are kept apart by a line break, which the tokenizer reads as a separator, so the
# facets can be read back from the index as whole keywords ("emergency stop").
_KEYWORD_SEP = "\n"
SLOTS = 32  # privacy parts a twin may have in the search index
_SHIFT = 5  # log2(SLOTS)

# Snippets are built from escaped text, so a document can never inject markup into a result.


def write_search_rows(c: sqlite3.Connection, twin_id: int, rows: list[SearchRow]) -> None:
    delete_search_rows(c, twin_id)
    levels = sorted({r.privacy for r in rows}, key=level_order)
    if len(levels) > SLOTS or (len(levels) == SLOTS and "public" not in levels):
        raise ValueError(f"a twin may have at most {SLOTS - 1} non-public privacy parts")
    slots = {lv: i + (lv != "public" and "public" not in levels) for i, lv in enumerate(levels)}
    parts: dict[str, dict[str, list[str]]] = {}
    for row in rows:
        row_id = c.execute(
            "INSERT INTO search_rows(twin_id, privacy, feature) VALUES (?, ?, ?)",
            (twin_id, row.privacy, row.feature),
        ).lastrowid
        keywords = _KEYWORD_SEP.join(row.keywords)
        c.execute(
            "INSERT INTO search_fts(rowid, name, description, keywords, extra)"
            " VALUES (?, ?, ?, ?, ?)",
            (row_id, row.name, row.description, keywords, row.extra),
        )
        c.executemany(
            "INSERT INTO search_keywords(row_id, keyword) VALUES (?, ?)",
            [(row_id, k) for k in dict.fromkeys(row.keywords)],
        )
        doc = parts.setdefault(
            row.privacy, {k: [] for k in ("name", "features", "kw", "desc", "x")}
        )
        doc["name" if row.feature is None else "features"].append(row.name)
        doc["kw"].append(keywords)
        doc["desc"].append(row.description)
        doc["x"].append(row.extra)
    for level, doc in parts.items():
        doc_id = (twin_id << _SHIFT) + slots[level]
        c.execute(
            "INSERT INTO search_parts(id, twin_id, privacy) VALUES (?, ?, ?)",
            (doc_id, twin_id, level),
        )
        c.execute(
            "INSERT INTO search_twins(rowid, name, features, keywords, description, extra)"
            " VALUES (?, ?, ?, ?, ?, ?)",
            (doc_id, *(_KEYWORD_SEP.join(doc[k]) for k in ("name", "features", "kw", "desc", "x"))),
        )


def delete_search_rows(c: sqlite3.Connection, twin_id: int) -> None:
    c.execute(
        "DELETE FROM search_fts WHERE rowid IN (SELECT id FROM search_rows WHERE twin_id = ?)",
        (twin_id,),
    )
    c.execute("DELETE FROM search_rows WHERE twin_id = ?", (twin_id,))
    c.execute(
        "DELETE FROM search_twins WHERE rowid IN (SELECT id FROM search_parts WHERE twin_id = ?)",
        (twin_id,),
    )
    c.execute("DELETE FROM search_parts WHERE twin_id = ?", (twin_id,))


def fts_phrase(word: str, prefix: bool = True) -> str:
    """One word as an FTS5 string, quoted so it is never read as query syntax. A prefix match
    for words of two letters or more; one letter as a prefix would match nearly everything."""
    quoted = '"' + word.replace('"', '""') + '"'
    return quoted + "*" if prefix and len(word) > 1 else quoted


def match_expression(words: list[str]) -> str:
    """Every word must match. `extra` (addresses, requirements, contacts) matches nearly any
    prefix, so there a word must match whole."""
    return " AND ".join(
        f"(({{name features keywords description}} : {fts_phrase(w)}) OR ({{extra}} : "
        f"{fts_phrase(w, prefix=False)}))"
        for w in words
    )


def names_expression(words: list[str]) -> str:
    """Every word matches the twin's name or a feature's name."""
    return " AND ".join(f"({{name features}} : {fts_phrase(w)})" for w in words)


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
            lambda c: _Search(c, vis, keyword).run(terms, limit, offset, facet_limit)
        )


class _Search:
    def __init__(self, c: sqlite3.Connection, vis: Visibility, keyword: str | None) -> None:
        self.c = c
        self.vis = vis
        self.keyword = keyword

    def run(self, terms: list[str], limit: int, offset: int, facet_limit: int) -> SearchResult:
        want = max(offset + limit, FACET_SAMPLE)
        ranked, total = self._ranked(terms, want) if terms else self._all()
        page = ranked[offset : offset + limit]
        names = self._names(page)
        matches = self._matches(page, terms) if terms else {}
        hits = [
            {
                "slug": names[t][0],
                "name": names[t][1],
                "score": round(score, 3),
                "matches": matches.get(t, []),
            }
            for t, score in page
        ]
        facets = self._facets([t for t, _ in ranked[:FACET_SAMPLE]], facet_limit)
        return SearchResult(
            total=total, hits=hits, facets=facets, facet_hits=min(len(ranked), FACET_SAMPLE)
        )

    def _keyword_filter(self, twin_expr: str) -> tuple[str, list[object]]:
        if not self.keyword:
            return "", []
        visible, args = part_visible(self.vis, "s.twin_id", "s.privacy")
        return (
            f" AND {twin_expr} IN (SELECT s.twin_id FROM search_keywords k JOIN search_rows s"
            f" ON s.id = k.row_id WHERE k.keyword = ? AND {visible})",
            [self.keyword, *args],
        )

    def _doc_filters(self) -> tuple[str, list[object]]:
        """Keeps the search_twins documents (parts) the reader may see; public parts (slot 0)
        pass without a lookup."""
        sql, args = self._keyword_filter(f"(rowid >> {_SHIFT})")
        if self.vis.is_admin:
            return sql, args
        private, private_args = visible_private_parts(self.vis)
        return (
            # Uncorrelated, so SQLite builds the set of the reader's non-public parts once.
            f" AND (rowid & {SLOTS - 1} = 0 OR rowid IN ({private})){sql}",
            [*private_args, *args],
        )

    def _ranked(self, terms: list[str], want: int) -> tuple[list[tuple[int, float]], int]:
        """The best `want` twins and the total.

        bm25 in FTS5 scores every document it ranks, so a broad word ("d", "data") costs as
        much as it matches. Up to RANK_LIMIT matching parts are all ranked; beyond that, only
        the parts whose names (the twin's or a feature's) match every word are ranked, and
        the other matches follow them unranked: a query that broad is narrowed by the next
        word typed, and its answer stays fast.
        """
        full = match_expression(terms)
        where, args = self._doc_filters()
        parts, total = self.c.execute(
            f"SELECT count(*), count(DISTINCT rowid >> {_SHIFT}) FROM search_twins"
            f" WHERE search_twins MATCH ?{where}",
            [full, *args],
        ).fetchone()
        if parts <= RANK_LIMIT:
            return self._top(full, want), total
        strong = names_expression(terms)
        best = dict(self._top(strong, want))
        if len(best) < want:
            for twin_id, score in self.c.execute(
                f"SELECT rowid >> {_SHIFT}, 0.0 FROM search_twins WHERE search_twins MATCH ?"
                f"{where} LIMIT ?",
                [f"({full}) NOT ({strong})", *args, 2 * want],
            ):
                best.setdefault(twin_id, score)
        return list(best.items())[:want], total

    def _top(self, expr: str, want: int) -> list[tuple[int, float]]:
        """The best `want` twins for one FTS expression, ranked by bm25."""
        where, args = self._doc_filters()
        # Most twins match with one part, so a little more than `want` parts nearly always
        # holds `want` twins; when it does not, group by twin (exact, a little slower).
        fetch = want + want // 4 + 8
        rows = self.c.execute(
            f"SELECT rowid >> {_SHIFT}, -rank FROM search_twins WHERE search_twins MATCH ?"
            f"{where} ORDER BY rank LIMIT ?",
            [expr, *args, fetch],
        ).fetchall()
        best: dict[int, float] = {}
        for twin_id, score in rows:
            best.setdefault(twin_id, score)
        if len(rows) == fetch and len(best) < want:
            rows = self.c.execute(
                f"SELECT rowid >> {_SHIFT} AS t, max(-rank) AS s FROM search_twins"
                f" WHERE search_twins MATCH ?{where} GROUP BY t ORDER BY s DESC LIMIT ?",
                [expr, *args, want],
            ).fetchall()
            best = dict(rows)
        return list(best.items())[:want]

    def _all(self) -> tuple[list[tuple[int, float]], int]:
        where, args = self._keyword_filter("t.id")
        if not self.vis.is_admin:
            visible, vis_args = part_visible(self.vis, "p.twin_id", "p.privacy")
            where = (
                " AND EXISTS (SELECT 1 FROM search_parts p WHERE p.twin_id = t.id"
                f" AND {visible}){where}"
            )
            args = [*vis_args, *args]
        rows = self.c.execute(
            f"SELECT t.id FROM twins t WHERE 1{where} ORDER BY t.name COLLATE NOCASE, t.slug", args
        ).fetchall()
        return [(r[0], 0.0) for r in rows], len(rows)

    def _names(self, page: list[tuple[int, float]]) -> dict[int, tuple[str, str]]:
        ids = [t for t, _ in page]
        if not ids:
            return {}
        marks = ", ".join("?" * len(ids))
        rows = self.c.execute(f"SELECT id, slug, name FROM twins WHERE id IN ({marks})", ids)
        return {r[0]: (r[1], r[2]) for r in rows}

    def _matches(
        self, page: list[tuple[int, float]], terms: list[str]
    ) -> dict[int, list[dict[str, Any]]]:
        """Which rows of the page's twins (the twin itself, or features) match any word, with
        a snippet each."""
        ids = [t for t, _ in page]
        if not ids:
            return {}
        visible, args = part_visible(self.vis, "s.twin_id", "s.privacy")
        marks = ", ".join("?" * len(ids))
        candidates = self.c.execute(
            f"SELECT s.id, s.twin_id, s.feature, s.privacy FROM search_rows s"
            f" WHERE s.twin_id IN ({marks}) AND {visible} ORDER BY s.feature IS NOT NULL, s.id",
            [*ids, *args],
        ).fetchall()
        snippets = self._snippets([r[0] for r in candidates], terms)
        out: dict[int, dict[str | None, dict[str, Any]]] = {}
        for row_id, twin_id, feature, privacy in candidates:
            if row_id not in snippets:
                continue
            entry = out.setdefault(twin_id, {}).setdefault(
                feature, {"feature": feature, "privacy": privacy}
            )
            entry.setdefault("snippet", snippets[row_id])
        return {t: list(features.values()) for t, features in out.items()}

    def _snippets(self, row_ids: list[int], terms: list[str]) -> dict[int, str]:
        """Snippets of the rows that match a word, made here from the stored text: a MATCH
        restricted to a list of rowids would run the whole query once per rowid."""
        out = {}
        highlighter = Highlighter(terms)
        for start in range(0, len(row_ids), 500):
            chunk = row_ids[start : start + 500]
            marks = ", ".join("?" * len(chunk))
            for row_id, *columns in self.c.execute(
                f"SELECT rowid, name, description, keywords, extra FROM search_fts"
                f" WHERE rowid IN ({marks})",
                chunk,
            ):
                snippet = highlighter.snippet(columns[:3], columns[3])
                if snippet is not None:
                    out[row_id] = snippet
        return out

    def _facets(self, twin_ids: list[int], limit: int) -> list[tuple[str, int]]:
        """Keyword counts (twins per keyword) over the visible parts of `twin_ids`."""
        if not twin_ids:
            return []
        visible, args = part_visible(self.vis, "p.twin_id", "p.privacy")
        marks = ", ".join("?" * len(twin_ids))
        docs = [
            r[0]
            for r in self.c.execute(
                f"SELECT p.id FROM search_parts p WHERE p.twin_id IN ({marks}) AND {visible}",
                [*twin_ids, *args],
            )
        ]
        if not docs:
            return []
        per_twin: dict[int, set[str]] = {}
        spelling: dict[str, str] = {}
        marks = ", ".join("?" * len(docs))
        for doc_id, keywords in self.c.execute(
            f"SELECT rowid, keywords FROM search_twins WHERE rowid IN ({marks})", docs
        ):
            folded = keywords.lower().split(_KEYWORD_SEP)
            per_twin.setdefault(doc_id >> _SHIFT, set()).update(folded)
            for low, keyword in zip(folded, keywords.split(_KEYWORD_SEP), strict=False):
                if low not in spelling:
                    spelling[low] = keyword
        counts = Counter(k for keywords in per_twin.values() for k in keywords if k)
        ranked = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:limit]
        return [(spelling[k], n) for k, n in ranked]
