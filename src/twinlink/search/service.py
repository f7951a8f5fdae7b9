"""Turns what a person types into ranked, permission-filtered hits with facets.

Twins (with the features that matched) come from the search index; library assets the
caller may read follow them, as hits of kind `asset`, in the same pages and total.
"""

from __future__ import annotations

import re
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.domain.library import AssetRecord
from twinlink.library.service import LibraryService
from twinlink.store.search import SearchStore

_WORD = re.compile(r"\w+", re.UNICODE)
MAX_TERMS = 8


def query_terms(text: str) -> list[str]:
    """The words of a query, lower-cased, without repeats, at most MAX_TERMS. The store
    matches each as a prefix ("histor" finds "historical" as you type), except one letter,
    which as a prefix would match nearly everything."""
    return list(dict.fromkeys(w.lower() for w in _WORD.findall(text)))[:MAX_TERMS]


def asset_hit(asset: AssetRecord) -> dict[str, Any]:
    return {
        "kind": "asset",
        "slug": None,
        "name": asset.name,
        "score": 0.0,
        "matches": [],
        "ref": asset.ref,
        "scope": asset.scope,
        "asset_kind": asset.kind,
        "description": asset.description,
    }


class SearchService:
    def __init__(self, store: SearchStore, library: LibraryService | None = None) -> None:
        self.store = store
        self.library = library

    async def search(
        self, principal: Principal, text: str, *, keyword: str | None, limit: int, offset: int
    ) -> dict[str, Any]:
        terms = query_terms(text)
        result = await self.store.search(
            principal.visibility, terms, keyword=keyword, limit=limit, offset=offset
        )
        hits = [{"kind": "twin", **hit} for hit in result.hits]
        total = result.total
        if self.library is not None:
            # The assets come after every twin: this page holds those past the twins.
            assets, asset_total = await self.library.search_assets(
                principal, terms, keyword=keyword, limit=limit - len(hits),
                offset=max(0, offset - result.total),
            )  # fmt: skip
            hits += [asset_hit(a) for a in assets]
            total += asset_total
        return {
            "query": text,
            "keyword": keyword,
            "total": total,
            "limit": limit,
            "offset": offset,
            "hits": hits,
            "facets": {
                "keywords": [{"value": k, "count": n} for k, n in result.facets],
                "counted_hits": result.facet_hits,
            },
        }
