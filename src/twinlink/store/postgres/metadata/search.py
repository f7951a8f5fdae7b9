"""Full-text search over twins and features with PostgreSQL's text search (tables:
migrations/0020_search.sql), with the semantics of the SQLite backend's (store/sqlite/search.py).

A twin is a hit when every word of the query matches one privacy part of it the reader may
see: as a prefix in the part's names, keywords and descriptions, or whole in its other text
(one-letter words always whole). Hits are ranked by ts_rank over one document per part with
the SQLite backend's weights (index.py); the features that matched, with snippets, are then
looked up for the page of hits only, and the keyword facets counted over the best hits.
"""

from __future__ import annotations

from collections import Counter
from typing import Any

from twinlink.domain.records import SearchResult, Visibility
from twinlink.store.postgres.db import Connection, PostgresDatabase
from twinlink.store.postgres.metadata.index import (
    DOC_WEIGHTS,
    EXTRA_WEIGHT,
    KEYWORD_SEP,
    term_query,
)
from twinlink.store.postgres.metadata.sql import Args
from twinlink.store.postgres.metadata.visibility import part_visible
from twinlink.store.snippets import Highlighter

FACET_SAMPLE = 100  # facets count the best this many hits
RANK_LIMIT = 2000  # matching parts ranked in full; above, only name matches are
_SCORE_SCALE = 10.0  # ts_rank's values are small: scaled so three decimals tell hits apart


class SearchTables:
    db: PostgresDatabase

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
        # One snapshot for all its queries: the count, the page and its matches agree.
        async with (
            self.db.connection() as conn,
            conn.transaction(isolation="repeatable_read", readonly=True),
        ):
            return await _Search(conn, vis, keyword).run(terms, limit, offset, facet_limit)


class _Search:
    def __init__(self, conn: Connection, vis: Visibility, keyword: str | None) -> None:
        self.conn = conn
        self.vis = vis
        self.keyword = keyword

    async def run(
        self, terms: list[str], limit: int, offset: int, facet_limit: int
    ) -> SearchResult:
        want = max(offset + limit, FACET_SAMPLE)
        ranked, total = await (self._ranked(terms, want) if terms else self._all())
        page = ranked[offset : offset + limit]
        names = await self._names(page)
        matches = await self._matches(page, terms) if terms else {}
        hits = [
            {
                "slug": names[t][0],
                "name": names[t][1],
                "score": round(score * _SCORE_SCALE, 3),
                "matches": matches.get(t, []),
            }
            for t, score in page
        ]
        facets = await self._facets([t for t, _ in ranked[:FACET_SAMPLE]], facet_limit)
        return SearchResult(
            total=total, hits=hits, facets=facets, facet_hits=min(len(ranked), FACET_SAMPLE)
        )

    def _filters(self, args: Args) -> str:
        """The parts (p) the reader may see, of twins holding the keyword if one is asked."""
        sql = " AND " + part_visible(self.vis, "p.twin_id", "p.privacy", args)
        if self.keyword:
            visible = part_visible(self.vis, "s.twin_id", "s.privacy", args)
            sql += (
                " AND p.twin_id IN (SELECT s.twin_id FROM search_keywords k JOIN search_rows s"
                f" ON s.id = k.row_id WHERE lower(k.keyword) = lower({args(self.keyword)})"
                f" AND {visible})"
            )
        return sql

    def _match(self, terms: list[str], args: Args, names_only: bool = False) -> str:
        """Every word matches the part (p): a prefix of its doc's words, or a whole word of
        its extra text; with `names_only`, a prefix of the twin's or a feature's name."""
        clauses = []
        for term in terms:
            doc = term_query(term, prefix=True, weights="AB" if names_only else "")
            assert doc is not None  # _ranked answers queries of such words itself
            clause = f"p.doc @@ {args(doc)}::tsquery"
            if not names_only:
                extra = term_query(term, prefix=False)
                clause = f"({clause} OR p.extra @@ {args(extra)}::tsquery)"
            clauses.append(clause)
        return " AND ".join(clauses)

    def _rank(self, terms: list[str], args: Args) -> str:
        """How well a part matches: any word counts, weighted as index.py says."""
        doc = " | ".join(q for t in terms if (q := term_query(t, prefix=True)))
        extra = " | ".join(q for t in terms if (q := term_query(t, prefix=False)))
        return (
            f"(ts_rank('{DOC_WEIGHTS}', p.doc, {args(doc or '')}::tsquery)"
            f" + {EXTRA_WEIGHT} * ts_rank(p.extra, {args(extra or '')}::tsquery))"
        )

    async def _ranked(self, terms: list[str], want: int) -> tuple[list[tuple[int, float]], int]:
        """The best `want` twins and the total. Up to RANK_LIMIT matching parts are all
        ranked; beyond, only the parts whose names match every word are, and the other
        matches follow them unranked: a query that broad is narrowed by the next word typed,
        and its answer stays fast."""
        if any(term_query(t, prefix=False) is None for t in terms):
            return [], 0  # a word with no letters or digits ("_"), as in FTS5, or too long
        args = Args()
        where = self._match(terms, args) + self._filters(args)
        row = await self.conn.fetchrow(
            f"SELECT count(*), count(DISTINCT p.twin_id) FROM search_parts p WHERE {where}", *args
        )
        assert row is not None
        parts, total = row
        if parts <= RANK_LIMIT:
            return await self._top(terms, want, names_only=False), total
        best = dict(await self._top(terms, want, names_only=True))
        if len(best) < want:
            args = Args()
            where = self._match(terms, args) + self._filters(args)
            rows = await self.conn.fetch(
                f"SELECT DISTINCT p.twin_id FROM search_parts p WHERE {where}"
                f" AND NOT (p.twin_id = ANY({args(list(best))}::bigint[]))"
                f" LIMIT {args(want - len(best))}",
                *args,
            )
            for r in rows:
                best.setdefault(r[0], 0.0)
        return list(best.items())[:want], total

    async def _top(
        self, terms: list[str], want: int, *, names_only: bool
    ) -> list[tuple[int, float]]:
        """The best `want` twins whose parts match, by their best part's rank."""
        args = Args()
        rank = self._rank(terms, args)
        where = self._match(terms, args, names_only) + self._filters(args)
        rows = await self.conn.fetch(
            f"SELECT p.twin_id, max({rank}) AS score FROM search_parts p WHERE {where}"
            f" GROUP BY p.twin_id ORDER BY score DESC, p.twin_id LIMIT {args(want)}",
            *args,
        )
        return [(r[0], float(r[1])) for r in rows]

    async def _all(self) -> tuple[list[tuple[int, float]], int]:
        """No words: every twin the reader may see, by name (as SQLite's NOCASE sorts)."""
        args = Args()
        where = ""
        if not self.vis.is_admin or self.keyword:
            where = "WHERE EXISTS (SELECT 1 FROM search_parts p WHERE p.twin_id = t.id"
            where += f"{self._filters(args)})"
        rows = await self.conn.fetch(
            f'SELECT t.id FROM twins t {where} ORDER BY lower(t.name) COLLATE "C", t.slug',
            *args,
        )
        return [(r[0], 0.0) for r in rows], len(rows)

    async def _names(self, page: list[tuple[int, float]]) -> dict[int, tuple[str, str]]:
        if not page:
            return {}
        rows = await self.conn.fetch(
            "SELECT id, slug, name FROM twins WHERE id = ANY($1::bigint[])", [t for t, _ in page]
        )
        return {r[0]: (r[1], r[2]) for r in rows}

    async def _matches(
        self, page: list[tuple[int, float]], terms: list[str]
    ) -> dict[int, list[dict[str, Any]]]:
        """Which rows of the page's twins (the twin itself, or features) match any word, with
        a snippet each."""
        if not page:
            return {}
        args = Args()
        ids = args([t for t, _ in page])
        visible = part_visible(self.vis, "s.twin_id", "s.privacy", args)
        rows = await self.conn.fetch(
            "SELECT s.twin_id, s.feature, s.privacy, s.name, s.description, s.keywords, s.extra"
            f" FROM search_rows s WHERE s.twin_id = ANY({ids}::bigint[]) AND {visible}"
            " ORDER BY s.feature IS NOT NULL, s.id",
            *args,
        )
        highlighter = Highlighter(terms)
        out: dict[int, dict[str | None, dict[str, Any]]] = {}
        for twin_id, feature, privacy, name, description, keywords, extra in rows:
            snippet = highlighter.snippet([name, description, keywords], extra)
            if snippet is None:
                continue
            entry = out.setdefault(twin_id, {}).setdefault(
                feature, {"feature": feature, "privacy": privacy}
            )
            entry.setdefault("snippet", snippet)
        return {t: list(features.values()) for t, features in out.items()}

    async def _facets(self, twin_ids: list[int], limit: int) -> list[tuple[str, int]]:
        """Keyword counts (twins per keyword) over the visible parts of `twin_ids`."""
        if not twin_ids:
            return []
        args = Args()
        ids = args(twin_ids)
        visible = part_visible(self.vis, "p.twin_id", "p.privacy", args)
        rows = await self.conn.fetch(
            "SELECT p.twin_id, p.keywords FROM search_parts p"
            f" WHERE p.twin_id = ANY({ids}::bigint[]) AND {visible}"
            # the order SQLite reads them in (twin, then public first), for the spelling
            " ORDER BY p.twin_id, p.privacy <> 'public', p.privacy",
            *args,
        )
        per_twin: dict[int, set[str]] = {}
        spelling: dict[str, str] = {}
        for twin_id, keywords in rows:
            folded = keywords.lower().split(KEYWORD_SEP)
            per_twin.setdefault(twin_id, set()).update(folded)
            for low, keyword in zip(folded, keywords.split(KEYWORD_SEP), strict=False):
                spelling.setdefault(low, keyword)
        counts = Counter(k for keywords in per_twin.values() for k in keywords if k)
        ranked = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:limit]
        return [(spelling[k], n) for k, n in ranked]
