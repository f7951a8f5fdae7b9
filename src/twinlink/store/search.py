"""The interface of the search index (SQLite FTS5 now, PostgreSQL full-text search later).

Search has its own protocol rather than living in the registry: what it finds grows beyond
the registry's twins and features (library assets, remote twins), and a backend may keep its
index apart from the metadata. `SearchService` reaches it only through this; the SQLite
metadata store implements it beside `MetadataStore`.
"""

from __future__ import annotations

from typing import Protocol

from twinlink.domain.records import SearchResult, Visibility


class SearchStore(Protocol):
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
        """Twins and features the visibility allows that hold every term (each a prefix,
        ranked), one page of them from `offset`, with the total and the keyword facets
        counted over the first hits."""
        ...
