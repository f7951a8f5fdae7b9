"""The metadata store on PostgreSQL (store/postgres/metadata/), against a real server
(_postgres.py): the store tests of tests/unit/test_sqlite_store.py that are not about SQLite's
own workings, and what only this backend has to get right (ids never reused, names unique
whatever their case, unique violations as conflicts, ordering whatever the locale)."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator

import asyncpg
import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.unit import test_sqlite_store
from tests.unit.test_sqlite_store import row, save, write
from twinlink.domain.errors import ConflictError, InvalidInputError, WriteConflictError
from twinlink.domain.records import AuditEntry, Edge, ServiceRecord, Visibility
from twinlink.store.postgres.db import PostgresDatabase, migrate
from twinlink.store.postgres.metadata import PostgresMetadataStore

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]

# test_sqlite_store's tests of any metadata store; the rest test SQLite's file, its
# migrations and its FTS5 ranking limit (this backend's own are below and in
# test_postgres_search.py).
for _name in (
    "test_search_needs_every_term_somewhere_in_the_twin",
    "test_name_match_outranks_description_match",
    "test_private_rows_are_filtered_and_facets_follow",
    "test_resaving_replaces_search_rows",
    "test_descendants_walk_and_exclusion",
    "test_write_is_atomic",
    "test_a_cycle_refuses_the_whole_batch",
    "test_self_parent_is_a_cycle",
    "test_deleting_keeps_relations_other_twins_declare",
    "test_snippets_escape_document_html",
    "test_the_gateway_audit_log_is_filtered_paged_and_pruned",
):
    globals()[_name] = getattr(test_sqlite_store, _name)


@pytest.fixture
async def store(postgres_dsn: str) -> AsyncIterator[PostgresMetadataStore]:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    metadata = PostgresMetadataStore(db)
    await metadata.open()
    try:
        yield metadata
    finally:
        await metadata.close()
        await db.close()


async def test_users_are_unique_and_found_whatever_the_case(store: PostgresMetadataStore) -> None:
    alice = await store.create_user("Alice", "hash", True, ["crew"], 5)
    with pytest.raises(WriteConflictError):
        await store.create_user("alice", None, False, [], 6)
    assert await store.get_user_by_name("ALICE") == alice
    assert alice.is_admin and alice.groups == ["crew"] and alice.password_hash == "hash"
    updated = await store.update_user(alice.id, is_admin=False, groups=[], disabled=True)
    assert updated is not None and not updated.is_admin and updated.disabled
    assert updated.password_hash == "hash"  # what was not given stays
    assert await store.count_users() == 1
    assert await store.delete_user(alice.id) and not await store.delete_user(alice.id)
    assert await store.update_user(alice.id, disabled=False) is None


async def test_tokens_are_found_touched_forward_only_and_revoked(
    store: PostgresMetadataStore,
) -> None:
    bob = await store.create_user("bob", None, False, [], 1)
    api = await store.create_token(bob.id, "ci", b"h1", "tl_1", "api", 10, None)
    session = await store.create_token(bob.id, "web", b"h2", "tl_2", "session", 11, 99)
    found = await store.find_token(b"h2")
    assert found is not None and found[0] == session and found[1] == bob
    assert await store.find_token(b"nope") is None
    await store.touch_tokens({api.id: 50, session.id: 40})
    await store.touch_tokens({api.id: 20})  # older: never moves the time back
    assert [t.last_used_ns for t in await store.list_tokens(bob.id)] == [50, 40]
    assert await store.revoke_tokens(bob.id, "session", 60) == 1
    assert await store.revoke_token(api.id, 61) and not await store.revoke_token(api.id, 62)
    assert [t.revoked_ns for t in await store.list_tokens(None)] == [61, 60]
    await store.delete_user(bob.id)
    assert await store.get_token(api.id) is None  # a user's tokens go with the user


async def test_ids_are_never_handed_out_twice(store: PostgresMetadataStore) -> None:
    first = await save(store, write("a", []))
    device = await store.create_device(first.id, "d", "", b"t1", "p", 1)
    await store.delete_twins([first])
    second = await save(store, write("a", []))
    assert second.id > first.id
    assert (await store.create_device(second.id, "d", "", b"t2", "p", 1)).id > device.id


async def test_devices_conflict_by_name_and_are_touched_forward_only(
    store: PostgresMetadataStore,
) -> None:
    twin = await save(store, write("crane", []))
    device = await store.create_device(twin.id, "plc", "the PLC", b"tok", "tl_d", 7)
    assert device.twin_slug == "crane" and device.last_seen_ns is None
    with pytest.raises(ConflictError, match="plc"):
        await store.create_device(twin.id, "plc", "", b"other", "tl_e", 8)
    await store.set_device_token(device.id, b"new", "tl_n")
    assert await store.find_device(b"tok") is None
    assert (await store.find_device(b"new")) == await store.get_device(twin.id, "plc")
    await store.touch_devices({device.id: 30})
    await store.touch_devices({device.id: 20})
    assert [d.last_seen_ns for d in await store.list_devices(twin.id)] == [30]
    await store.delete_device(device.id)
    assert await store.list_devices(twin.id) == []


async def test_names_sort_by_code_point_and_roles_by_user_name_without_case(
    store: PostgresMetadataStore,
) -> None:
    twin = await save(store, write("t", []))
    for name in ("b", "B", "a", "_x", "Z"):
        await store.create_device(twin.id, name, "", name.encode() + b"!", "p", 1)
    assert [d.name for d in await store.list_devices(twin.id)] == ["B", "Z", "_x", "a", "b"]
    for name in ("carol", "Bob", "alice"):
        user = await store.create_user(name, None, False, [], 1)
        await store.set_role(twin.id, user.id, "viewer")
    await store.set_role(twin.id, user.id, "editor")  # replaces
    assert [(n, r) for _, n, r in await store.list_roles(twin.id)] == [
        ("alice", "editor"), ("Bob", "viewer"), ("carol", "viewer"),
    ]  # fmt: skip
    assert await store.get_role(twin.id, user.id) == "editor"
    await store.set_role(twin.id, user.id, None)
    assert await store.get_role(twin.id, user.id) is None


async def test_twins_listed_by_visibility_name_role_keyword_and_page(
    store: PostgresMetadataStore,
) -> None:
    owner = await store.create_user("olga", None, False, [], 1)
    crane = write("crane", [row("public", "CAD", "CAD", "", ["CAD"])])
    vault = write("vault", [row("private", None, "Vault")], parts={"private": {}}, owner=owner.id)
    crew = write("crew-room", [row("crew", None, "Crew")], parts={"crew": {}})
    await store.save_twins([crane, vault, crew])
    anyone = Visibility()

    async def slugs(vis: Visibility, **kw: object) -> list[str]:
        return [t.slug for t in await store.list_twins(vis, limit=10, **kw)]  # type: ignore[arg-type]

    assert await slugs(anyone) == ["crane"]
    assert await slugs(Visibility(user_id=owner.id)) == ["crane", "vault"]
    assert await slugs(Visibility(groups=("crew",))) == ["crane", "crew-room"]
    assert await slugs(Visibility(is_admin=True), after_slug="crane") == ["crew-room", "vault"]
    assert await slugs(Visibility(is_admin=True), name_contains="RA") == ["crane"]
    assert await slugs(Visibility(is_admin=True), name_contains="%") == []
    assert await slugs(Visibility(is_admin=True), role_user_id=owner.id) == ["vault"]
    assert await slugs(anyone, keyword="cad") == ["crane"]
    record = await store.get_twin("vault")
    assert record is not None and record.visibility == "private" and record.levels == ["private"]
    assert await store.get_parts(record.id) == {"private": {}}
    assert set(await store.get_twins_by_dt_ids(["urn:crane", "urn:none"])) == {"urn:crane"}
    assert await store.twin_ids() == {t.id for t in await store.list_twins(
        Visibility(is_admin=True), limit=10)}  # fmt: skip


async def test_a_cycle_among_twins_already_stored_is_refused(store: PostgresMetadataStore) -> None:
    await save(store, write("a", [], edges=[Edge("urn:a", "parent", "urn:b", "urn:a", "public")]))
    b = write("b", [], edges=[Edge("urn:b", "parent", "urn:a", "urn:b", "public")])
    with pytest.raises(ConflictError, match="cycle"):
        await save(store, b)
    assert await store.get_twin("b") is None


async def test_processors_their_events_and_fmus(store: PostgresMetadataStore) -> None:
    from twinlink.store.postgres.metadata import processors

    twin = await save(store, write("t", []))
    made = await store.create_processor(twin.id, "sim", "fmu", {"a": [1, 2]}, True, None, 3)
    assert made.spec == {"a": [1, 2]} and made.twin_slug == "t" and made.enabled
    with pytest.raises(ConflictError, match="sim"):
        await store.create_processor(twin.id, "sim", "fmu", {}, True, None, 4)
    await store.update_processor(made.id, {"b": 1}, False, 9)
    [stored] = await store.list_processors(twin.id)
    assert (stored.spec, stored.enabled, stored.modified_ns) == ({"b": 1}, False, 9)
    kept = processors.EVENTS_KEPT
    events = [
        (made.id, t, "started" if t % 2 else "alarm", f"m{t}", {"t": t}) for t in range(kept + 5)
    ]
    await store.add_processor_events([*events, (made.id + 99, 1, "x", "no such processor", {})])
    newest = await store.list_processor_events(made.id, limit=kept + 10)
    assert len(newest) == kept and newest[0].data == {"t": kept + 4} and newest[-1].time_ns == 5
    alarms = await store.list_processor_events(made.id, 2, before_id=newest[0].id, kind="alarm")
    assert [e.message for e in alarms] == [f"m{kept + 2}", f"m{kept}"]
    fmu = await store.put_fmu(twin.id, "m.fmu", "ab", 10, {"v": 1}, None, 5)
    again = await store.put_fmu(twin.id, "m.fmu", "cd", 11, {"v": 2}, None, 6)
    assert again.id == fmu.id and (again.sha256, again.info) == ("cd", {"v": 2})
    assert await store.list_fmus(twin.id) == [again]
    assert await store.delete_fmu(twin.id, "m.fmu") and not await store.delete_fmu(twin.id, "m.fmu")
    await store.delete_processor(made.id)
    assert await store.list_processors() == []
    assert await store.list_processor_events(made.id, 10) == []


async def test_services_and_connectors(store: PostgresMetadataStore) -> None:
    twin = await save(store, write("t", []))
    record = ServiceRecord(0, twin.id, "cad", "api", {"url": "http://x"}, b"sealed", "http://x:80",
                           None, 1, 1)  # fmt: skip
    made = await store.put_service(record, create=True)
    assert (made.settings, made.secret) == ({"url": "http://x"}, b"sealed")
    with pytest.raises(ConflictError, match="cad"):
        await store.put_service(record, create=True)
    record.settings, record.secret, record.modified_ns = {"url": "http://y"}, None, 2
    changed = await store.put_service(record, create=False)
    assert (changed.id, changed.settings, changed.secret) == (made.id, {"url": "http://y"}, None)
    assert await store.list_services() == [changed] == await store.list_services(twin.id)
    assert await store.delete_service(twin.id, "cad") and not await store.delete_service(
        twin.id, "cad"
    )

    device = await store.create_device(twin.id, "d", "", b"tok", "p", 1)
    conn = await store.create_connector(twin.id, device.id, "udp", "udp", {"port": 1}, b"s",
                                        True, None, 4)  # fmt: skip
    assert (conn.device, conn.twin_slug, conn.secret, conn.enabled) == ("d", "t", b"s", True)
    with pytest.raises(ConflictError, match="udp"):
        await store.create_connector(twin.id, device.id, "udp", "udp", {}, None, True, None, 5)
    await store.update_connector(conn.id, {"port": 2}, None, False, 6)
    [stored] = await store.list_connectors(twin.id)
    assert (stored.settings, stored.secret, stored.enabled, stored.modified_ns) == (
        {"port": 2}, None, False, 6)  # fmt: skip
    await store.delete_device(device.id)  # its connectors go with it
    assert await store.list_connectors() == []


async def test_the_audit_log_keeps_entries_of_twins_that_are_gone(
    store: PostgresMetadataStore,
) -> None:
    twin = await save(store, write("t", []))
    entry = AuditEntry(5, "t", "cad", "alice", "GET", "/x", 200, "forwarded", 1, 2, None, 3.5)
    await store.add_audit([entry], keep_after_ns=0)
    await store.delete_twins([twin])
    [kept] = await store.list_audit({"twins": ["t"], "since_ns": 5, "until_ns": 6}, limit=5)
    assert kept.upstream_ms is None and kept.total_ms == 3.5 and kept.id > 0
    assert await store.ping()


async def test_text_with_a_nul_character_is_refused_saying_so(
    store: PostgresMetadataStore,
) -> None:
    """PostgreSQL's text cannot hold U+0000 (SQLite's can): a 422 that says so, not a 500,
    and nothing of the write stored."""
    with pytest.raises(InvalidInputError, match="NUL"):
        await save(store, write("t", [row("public", None, "T", "a \x00 b")]))
    assert await store.count_twins() == 0
    with pytest.raises(InvalidInputError, match="NUL"):
        await store.list_twins(Visibility(), limit=5, after_slug="\x00weird")
    with pytest.raises(InvalidInputError, match="NUL"):
        await store.search(Visibility(), ["t"], keyword="\x00", limit=5, offset=0)


async def test_a_row_that_names_one_deleted_meanwhile_is_a_conflict(
    store: PostgresMetadataStore,
) -> None:
    """As SQLite's IntegrityError: a foreign key broken by a request that ran at the same
    time is a WriteConflictError (409, retry), not a database error."""
    twin = await save(store, write("t", []))
    gone = await store.create_user("gone", None, False, [], 1)
    await store.delete_user(gone.id)
    with pytest.raises(WriteConflictError):
        await store.set_role(twin.id, gone.id, "viewer")
    with pytest.raises(WriteConflictError):
        await store.create_token(gone.id, "t", b"h", "p", "api", 1, None)
    await store.delete_twins([twin])
    with pytest.raises(WriteConflictError):
        await store.put_fmu(twin.id, "m.fmu", "ab", 1, {}, None, 1)


async def test_two_writers_cannot_each_add_half_of_a_cycle(store: PostgresMetadataStore) -> None:
    """Two saves at once (two nodes), each declaring one edge of a cycle: one is refused,
    whichever comes second, as SQLite's one writer at a time refuses it."""
    for n in range(5):
        a, b = f"urn:a{n}", f"urn:b{n}"
        first = write(f"a{n}", [], edges=[Edge(a, "parent", b, a, "public")])
        second = write(f"b{n}", [], edges=[Edge(b, "parent", a, b, "public")])
        results = await asyncio.gather(
            store.save_twins([first]), store.save_twins([second]), return_exceptions=True
        )
        refused = [r for r in results if isinstance(r, ConflictError)]
        assert len(refused) == 1, results
        assert await store.descendants([a], exclude="none") != await store.descendants(
            [b], exclude="none"
        )


async def test_a_database_of_an_older_version_is_upgraded_keeping_its_users(
    postgres_dsn: str,
) -> None:
    conn = await asyncpg.connect(postgres_dsn)
    try:
        applied = await migrate(conn, target=10)  # the metadata, before the search index
        assert applied[-1] == 10
        await conn.execute("INSERT INTO users (username, created_ns) VALUES ('Old', 1)")
    finally:
        await conn.close()
    db = PostgresDatabase(postgres_dsn)
    await db.open()  # migrates the rest
    try:
        store = PostgresMetadataStore(db)
        old = await store.get_user_by_name("old")
        assert old is not None and old.groups == [] and not old.is_admin
        await save(store, write("crane", [row("public", None, "Crane")]))
        found = await store.search(Visibility(), ["cra"], keyword=None, limit=5, offset=0)
        assert [h["slug"] for h in found.hits] == ["crane"]
    finally:
        await db.close()
