"""Search on PostgreSQL finds what search on SQLite finds: the example twins applied to both
backends' metadata stores, the same queries asked of both (prefixes, every word required,
one-letter words, query syntax characters, diacritics, keyword filters, privacy, paging)
give the same totals, hits, matched features with the same snippets, and the same facets.
Ranking is each backend's own (bm25 against ts_rank, with the same weights): where the test
compares order it is where one hit is clearly better."""

from __future__ import annotations

from collections.abc import AsyncIterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._util import CRANE_SLUG, example_documents
from tests.unit.test_sqlite_store import row, save, write
from twinlink.auth.rights import Principal
from twinlink.domain.records import SearchResult, User, Visibility
from twinlink.registry.documents import parse_documents
from twinlink.registry.service import RegistryService
from twinlink.search.service import query_terms
from twinlink.store.base import MetadataStore
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata import PostgresMetadataStore
from twinlink.store.sqlite import SqliteStore

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]

QUERIES = [
    "", "cad", "CAD", "crane cad", "historical", "histor", "real", "data", "K16052", "q", "d",
    "_", "__init__", "name:crane", "crane*", "-crane", "NEAR(a b)", "Åland ÄÖ", "saatio",
    "a" * 256, "😀", "opc ua", "temperature", "historian", "booking calendar", "monitoring",
    "ilmatar crane", "nothing-like-this",
]  # fmt: skip


@dataclass
class Backends:
    sqlite: MetadataStore
    postgres: PostgresMetadataStore
    admins: dict[str, User]


async def _apply_examples(store: MetadataStore) -> User:
    admin = await store.create_user("admin", None, True, [], 1)
    registry = RegistryService(store, "http://x")
    for path in example_documents():
        docs = parse_documents(path.read_bytes(), "application/yaml", 10 * 2**20)
        await registry.apply(Principal(admin), docs)
    return admin


@pytest.fixture
async def backends(postgres_dsn: str, tmp_path: Path) -> AsyncIterator[Backends]:
    sqlite = SqliteStore(tmp_path)
    db = PostgresDatabase(postgres_dsn)
    await sqlite.open()
    await db.open()
    postgres = PostgresMetadataStore(db)
    try:
        admins = {"sqlite": await _apply_examples(sqlite)}
        admins["postgres"] = await _apply_examples(postgres)
        yield Backends(sqlite, postgres, admins)
    finally:
        await db.close()
        await sqlite.close()


def _found(result: SearchResult) -> dict[str, Any]:
    """What must agree: the total, each hit with its matches, the facets."""
    return {
        "total": result.total,
        "hits": {h["slug"]: (h["name"], h["matches"]) for h in result.hits},
        "facets": sorted(result.facets),
        "facet_hits": result.facet_hits,
    }


async def _both(
    b: Backends, vis: Visibility, q: str, keyword: str | None = None, **page: int
) -> tuple[SearchResult, SearchResult]:
    args: dict[str, Any] = {"keyword": keyword, "limit": 200, "offset": 0, **page}
    terms = query_terms(q)
    return (
        await b.sqlite.search(vis, terms, **args),
        await b.postgres.search(vis, terms, **args),
    )


@pytest.mark.parametrize("keyword", [None, "CAD", "real-time"])
async def test_the_same_queries_find_the_same_on_both_backends(
    backends: Backends, keyword: str | None
) -> None:
    for q in QUERIES:
        lite, pg = await _both(backends, Visibility(is_admin=True), q, keyword)
        assert _found(pg) == _found(lite), (q, keyword)
        scores = [h["score"] for h in pg.hits]
        assert scores == sorted(scores, reverse=True), q


async def test_the_examples_are_found_at_all(backends: Backends) -> None:
    """The comparison above compares something: words find twins, one letter is no wildcard."""
    admin = Visibility(is_admin=True)
    _, every = await _both(backends, admin, "")
    _, cad = await _both(backends, admin, "cad")
    _, one_letter = await _both(backends, admin, "q")
    _, the_id = await _both(backends, admin, "K16052")
    assert every.total >= 3 and one_letter.total < every.total
    assert cad.hits[0]["slug"] == CRANE_SLUG and [h["slug"] for h in the_id.hits] == [CRANE_SLUG]
    snippets = [m["snippet"] for m in cad.hits[0]["matches"]]
    assert any("<mark>CAD</mark>" in s for s in snippets)
    facets = dict(cad.facets)
    assert facets["CAD"] >= 1


async def test_privacy_filters_the_same_on_both_backends(backends: Backends) -> None:
    for name, store in (("sqlite", backends.sqlite), ("postgres", backends.postgres)):
        reader = await store.create_user("reader", None, False, ["crew"], 1)
        crane = await store.get_twin(CRANE_SLUG)
        assert crane is not None
        await store.set_role(crane.id, reader.id, "viewer")
        assert name in backends.admins
    seen: dict[str, list[dict[str, Any]]] = {}
    for vis_of in (
        lambda user_id: Visibility(),
        lambda user_id: Visibility(user_id=user_id),
        # no role, a member of the crane's group part's group ("private" is never a group)
        lambda user_id: Visibility(user_id=user_id + 1, groups=("group-1", "private")),
    ):
        for q in QUERIES:
            # the reader has the same id in both: both stores made the same users in order
            vis = vis_of(backends.admins["postgres"].id + 1)
            lite, pg = await _both(backends, vis, q)
            assert _found(pg) == _found(lite), (q, vis)
            seen.setdefault(q, []).append(_found(pg))
    # the readers see different parts, so the comparisons above compared different answers
    anyone, viewer, member = zip(*seen.values(), strict=True)
    assert anyone != viewer and anyone != member
    assert seen["booking calendar"][0]["total"] == 0 < seen["booking calendar"][2]["total"]


async def test_pages_of_hits_follow_the_ranking(backends: Backends) -> None:
    admin = Visibility(is_admin=True)
    _, full = await _both(backends, admin, "data")
    assert full.total >= 2
    pages = [
        (await _both(backends, admin, "data", limit=1, offset=i))[1] for i in range(full.total)
    ]
    assert [p.hits[0]["slug"] for p in pages] == [h["slug"] for h in full.hits]
    assert {p.total for p in pages} == {full.total}


@pytest.fixture
async def store(postgres_dsn: str) -> AsyncIterator[PostgresMetadataStore]:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        yield PostgresMetadataStore(db)
    finally:
        await db.close()


async def test_broad_queries_rank_name_matches_and_count_everything(
    store: PostgresMetadataStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    from twinlink.store.postgres.metadata import search

    monkeypatch.setattr(search, "RANK_LIMIT", 2)  # as if the word matched thousands of parts
    await save(store, write("a", [row("public", None, "Alpha", "pump station")]))
    await save(store, write("b", [row("public", None, "Beta", "pump and pump")]))
    await save(store, write("c", [row("public", "Pump", "Pump", "moves water")]))
    result = await store.search(Visibility(), ["pump"], keyword=None, limit=5, offset=0)
    assert result.total == 3
    slugs = [h["slug"] for h in result.hits]
    assert slugs[0] == "c" and sorted(slugs[1:]) == ["a", "b"]  # the name match first


async def test_words_are_split_and_folded_as_unicode61_does(store: PostgresMetadataStore) -> None:
    """No parser or dictionary of PostgreSQL's: a URL, an e-mail address, a path and a
    hyphenated word are words like any other, nothing is stemmed, diacritics are folded."""
    text = (
        "see https://example.org/twins/crane-7 or ops@plant.fi, file /srv/data_2024.csv;"
        " running pumps"
    )
    await save(store, write("x", [row("public", None, "Säätiö", text)]))

    async def total(*terms: str) -> int:
        found = await store.search(Visibility(), list(terms), keyword=None, limit=5, offset=0)
        return found.total

    for words in (["example", "crane", "7"], ["plant"], ["srv", "2024"], ["saatio"], ["säät"],
                  ["runn"], ["data_2024"], ["crane", "https"]):  # fmt: skip
        assert await total(*words) == 1, words
    assert await total("run") == 1 and await total("pump") == 1  # prefixes
    assert await total("running", "pumping") == 0  # every word, and nothing stemmed
    assert await total("_") == 0 and await total("2025") == 0


async def test_text_past_what_a_tsvector_holds_is_stored_and_searched(
    store: PostgresMetadataStore,
) -> None:
    """PostgreSQL refuses a word over 2 046 bytes and a tsvector over 1 MiB: such a twin is
    still stored and found by its other words, and a query of such a word finds nothing
    instead of failing."""
    long_word = "x" * 3000
    many = " ".join(f"w{i}" for i in range(200_000))  # 1.3 MB of different words
    await save(store, write("big", [row("public", None, "Big", f"first {long_word} {many}")]))

    async def total(*terms: str) -> int:
        found = await store.search(Visibility(), list(terms), keyword=None, limit=5, offset=0)
        return found.total

    assert await total("big") == 1 and await total("first") == 1 and await total("w1") == 1
    assert await total(long_word) == 0 and await total("big", long_word) == 0
    assert await total("w199999") == 0  # past the limit, left out of the index
