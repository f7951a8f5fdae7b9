"""Turns what a person types into ranked, permission-filtered hits with facets."""

from __future__ import annotations

import re
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.store.search import SearchStore

_WORD = re.compile(r"\w+", re.UNICODE)
MAX_TERMS = 8


def query_terms(text: str) -> list[str]:
    """The words of a query, lower-cased, without repeats, at most MAX_TERMS. The store
    matches each as a prefix ("histor" finds "historical" as you type), except one letter,
    which as a prefix would match nearly everything."""
    return list(dict.fromkeys(w.lower() for w in _WORD.findall(text)))[:MAX_TERMS]


class SearchService:
    def __init__(self, store: SearchStore) -> None:
        self.store = store

    async def search(
        self, principal: Principal, text: str, *, keyword: str | None, limit: int, offset: int
    ) -> dict[str, Any]:
        result = await self.store.search(
            principal.visibility, query_terms(text), keyword=keyword, limit=limit, offset=offset
        )
        return {
            "query": text,
            "keyword": keyword,
            "total": result.total,
            "limit": limit,
            "offset": offset,
            "hits": result.hits,
            "facets": {
                "keywords": [{"value": k, "count": n} for k, n in result.facets],
                "counted_hits": result.facet_hits,
            },
        }
