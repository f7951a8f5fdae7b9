"""The SQLite store on a real file in a temporary folder (fast: no server)."""

from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.domain.errors import ConflictError, WriteConflictError
from twinlink.domain.records import Edge, SearchRow, TwinWrite, Visibility
from twinlink.store.sqlite import SqliteStore
from twinlink.store.sqlite.db import connect, migrate, migrations


def write(
    slug: str,
    rows: list[SearchRow],
    parts: dict | None = None,
    edges: list[Edge] | None = None,  # type: ignore[type-arg]
    owner: int | None = None,
) -> TwinWrite:
    return TwinWrite(
        slug=slug,
        dt_id=f"urn:{slug}",
        name=slug.title(),
        created_ns=1,
        modified_ns=1,
        parts=parts or {"public": {"name": slug}},
        edges=edges or [],
        search_rows=rows,
        owner_user_id=owner,
    )


def row(
    privacy: str,
    feature: str | None,
    name: str,
    description: str = "",
    keywords: list[str] | None = None,
) -> SearchRow:
    return SearchRow(privacy, feature, name, description, keywords or [], "")


async def save(store: SqliteStore, w: TwinWrite):  # type: ignore[no-untyped-def]
    return (await store.save_twins([w]))[0]


@pytest.fixture
async def store(tmp_path: Path):  # type: ignore[no-untyped-def]
    s = SqliteStore(tmp_path)
    await s.open()
    yield s
    await s.close()


def test_migrations_are_numbered_without_gaps() -> None:
    versions = [v for v, _, _ in migrations()]
    assert versions == list(range(1, len(versions) + 1))


async def test_existing_data_dir_is_upgraded_in_place(tmp_path: Path) -> None:
    conn = connect(tmp_path / SqliteStore.FILE_NAME)
    assert migrate(conn, target=1) == [1]
    conn.execute("INSERT INTO users(username, created_ns) VALUES ('old', 1)")
    conn.close()
    store = SqliteStore(tmp_path)
    await store.open()
    try:
        assert (await store.get_user_by_name("old")) is not None
        version = await store.db.read(lambda c: c.execute("PRAGMA user_version").fetchone()[0])
        assert version == migrations()[-1][0]
        await save(store, write("crane", [row("public", None, "Crane")]))
        assert (
            await store.search(Visibility(), ["crane"], keyword=None, limit=5, offset=0)
        ).total == 1
    finally:
        await store.close()


async def test_wal_mode(store: SqliteStore) -> None:
    assert await store.db.read(lambda c: c.execute("PRAGMA journal_mode").fetchone()[0]) == "wal"


async def test_search_needs_every_term_somewhere_in_the_twin(store: SqliteStore) -> None:
    await save(
        store,
        write(
            "crane",
            [
                row("public", None, "Ilmatar crane"),
                row("public", "CAD store", "CAD store", "3D model", ["CAD"]),
            ],
        ),
    )
    await save(store, write("hall", [row("public", None, "Hall", "a crane is here")]))
    result = await store.search(Visibility(), ["crane", "cad"], keyword=None, limit=5, offset=0)
    assert [h["slug"] for h in result.hits] == ["crane"]
    assert {m["feature"] for m in result.hits[0]["matches"]} == {None, "CAD store"}


async def test_name_match_outranks_description_match(store: SqliteStore) -> None:
    await save(store, write("a", [row("public", None, "Pump", "moves water")]))
    await save(store, write("b", [row("public", None, "Tank", "fed by a pump and a pump again")]))
    result = await store.search(Visibility(), ["pump"], keyword=None, limit=5, offset=0)
    assert [h["slug"] for h in result.hits] == ["a", "b"]


async def test_private_rows_are_filtered_and_facets_follow(store: SqliteStore) -> None:
    await save(
        store,
        write(
            "crane",
            [
                row("public", None, "Crane"),
                row("private", "Vault", "Vault", "zebra secrets", ["zebra"]),
            ],
            parts={"public": {"name": "Crane"}, "private": {}},
        ),
    )
    assert (await store.search(Visibility(), ["zebra"], keyword=None, limit=5, offset=0)).total == 0
    admin = await store.search(
        Visibility(is_admin=True), ["zebra"], keyword=None, limit=5, offset=0
    )
    assert admin.total == 1 and admin.facets == [("zebra", 1)]
    grouped = Visibility(user_id=99, groups=("private",))  # a group name never grants private
    assert (await store.search(grouped, ["zebra"], keyword=None, limit=5, offset=0)).total == 0


async def test_resaving_replaces_search_rows(store: SqliteStore) -> None:
    record = await save(store, write("t", [row("public", None, "Old name")]))
    update = write("t", [row("public", None, "New name")])
    update.twin_id = record.id
    await save(store, update)
    assert (await store.search(Visibility(), ["old"], keyword=None, limit=5, offset=0)).total == 0
    assert (await store.search(Visibility(), ["new"], keyword=None, limit=5, offset=0)).total == 1


async def test_descendants_walk_and_exclusion(store: SqliteStore) -> None:
    edges = [Edge("a", "parent", "b", "a", "public"), Edge("b", "parent", "c", "b", "public")]
    await save(store, write("x", [], edges=edges))
    assert await store.descendants(["a"], exclude="zz") == {"a", "b", "c"}
    assert await store.descendants(["a"], exclude="b") == {"a"}


async def test_write_is_atomic(store: SqliteStore) -> None:
    await save(store, write("dup", []))
    with pytest.raises(WriteConflictError):
        await save(store, write("dup", [row("public", None, "Second")]))
    assert await store.count_twins() == 1
    assert (
        await store.search(Visibility(), ["second"], keyword=None, limit=5, offset=0)
    ).total == 0


async def test_a_cycle_refuses_the_whole_batch(store: SqliteStore) -> None:
    a = write("a", [], edges=[Edge("urn:a", "parent", "urn:b", "urn:a", "public")])
    b = write(
        "b",
        [row("public", None, "Bee")],
        edges=[Edge("urn:b", "parent", "urn:a", "urn:b", "public")],
    )
    with pytest.raises(ConflictError, match="cycle"):
        await store.save_twins([a, b])
    assert await store.count_twins() == 0
    assert await store.edges_touching(["urn:a"]) == []
    await store.save_twins([a])  # alone, a's edge is fine


async def test_self_parent_is_a_cycle(store: SqliteStore) -> None:
    with pytest.raises(ConflictError):
        await store.save_twins(
            [write("a", [], edges=[Edge("urn:a", "parent", "urn:a", "urn:a", "public")])]
        )


async def test_deleting_keeps_relations_other_twins_declare(store: SqliteStore) -> None:
    hall = await save(
        store,
        write("hall", [], edges=[Edge("urn:hall", "parent", "urn:crane", "urn:hall", "public")]),
    )
    crane = await save(
        store,
        write("crane", [], edges=[Edge("urn:hall", "parent", "urn:crane", "urn:crane", "public")]),
    )
    await store.delete_twins([crane])
    assert [e.declared_by for e in await store.edges_touching(["urn:crane"])] == ["urn:hall"]
    await store.delete_twins([hall])
    assert await store.edges_touching(["urn:crane"]) == []


async def test_snippets_escape_document_html(store: SqliteStore) -> None:
    await save(store, write("x", [row("public", "F", "F", "<b onmouseover=x>crane</b> here")]))
    result = await store.search(Visibility(), ["crane"], keyword=None, limit=5, offset=0)
    snippet = result.hits[0]["matches"][0]["snippet"]
    assert "<b" not in snippet
    assert "onmouseover=x&gt;<mark>crane</mark>&lt;/b&gt; here" in snippet


async def test_broad_queries_rank_name_matches_and_count_everything(
    store: SqliteStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    from twinlink.store.sqlite import search

    monkeypatch.setattr(search, "RANK_LIMIT", 2)  # as if the word matched thousands of parts
    await save(store, write("a", [row("public", None, "Alpha", "pump station")]))
    await save(store, write("b", [row("public", None, "Beta", "pump and pump")]))
    await save(store, write("c", [row("public", "Pump", "Pump", "moves water")]))
    result = await store.search(Visibility(), ["pump"], keyword=None, limit=5, offset=0)
    assert result.total == 3
    slugs = [h["slug"] for h in result.hits]
    assert slugs[0] == "c" and sorted(slugs[1:]) == ["a", "b"]  # the name match first


async def test_the_gateway_audit_log_is_filtered_paged_and_pruned(store: SqliteStore) -> None:
    from twinlink.domain.records import AuditEntry

    def entry(t: int, service: str, status: int) -> AuditEntry:
        return AuditEntry(
            t, "crane", service, "alice", "GET", "/x", status, "forwarded", 0, 9, 1.0, 2.0
        )

    await store.add_audit([entry(t, "historian" if t % 2 else "cad", 200) for t in range(1, 7)], 0)
    newest = await store.list_audit({"service": "historian"}, limit=2)
    assert [e.time_ns for e in newest] == [5, 3]
    older = await store.list_audit({"service": "historian"}, limit=2, before_id=newest[-1].id)
    assert [e.time_ns for e in older] == [1]
    assert await store.list_audit({"twins": []}, limit=10) == []
    await store.add_audit([entry(10, "cad", 502)], keep_after_ns=4)  # older than 4 ns go
    kept = await store.list_audit({}, limit=10)
    assert sorted(e.time_ns for e in kept) == [4, 5, 6, 10]
    assert [e.status for e in await store.list_audit({"status": 502}, limit=10)] == [502]
