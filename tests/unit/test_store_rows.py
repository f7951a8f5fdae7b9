"""The row -> record mappings both metadata backends share (store/rows.py): a SQLite row (its
booleans 0 and 1, read through sqlite3.Row) and a PostgreSQL-like row (real booleans, read by
name as asyncpg.Record is) give the same record."""

from __future__ import annotations

import sqlite3
from typing import Any

from twinlink.domain.records import AuditEntry, User
from twinlink.store.rows import (
    AUDIT_COLUMNS,
    USER_COLUMNS,
    audit_of,
    processor_of,
    twin_of,
    user_of,
)


def _sqlite_row(sql: str) -> sqlite3.Row:
    conn = sqlite3.connect(":memory:")
    try:
        conn.row_factory = sqlite3.Row
        row: sqlite3.Row = conn.execute(sql).fetchone()
        return row
    finally:
        conn.close()


def test_a_sqlite_row_and_a_postgres_row_read_alike() -> None:
    sqlite_row = _sqlite_row(
        "SELECT 7 AS id, 'ada' AS username, NULL AS password_hash, 1 AS is_admin,"
        " '[\"ops\"]' AS groups_json, 0 AS disabled, 42 AS created_ns"
    )
    postgres_row: dict[str, Any] = dict(zip(USER_COLUMNS.split(", "), sqlite_row, strict=True))
    postgres_row.update(is_admin=True, disabled=False)

    expected = User(id=7, username="ada", is_admin=True, groups=["ops"], created_ns=42)
    for row in (sqlite_row, postgres_row):
        user = user_of(row)
        assert user == expected
        assert user.is_admin is True and user.disabled is False  # not 1 and 0


def test_a_processor_s_spec_is_parsed_and_enabled_a_boolean() -> None:
    row = _sqlite_row(
        "SELECT 3 AS id, 1 AS twin_id, 'rig' AS slug, 'lp' AS name, 'lowpass' AS blueprint,"
        " '{\"cutoff_hz\": 2}' AS spec, 0 AS enabled, NULL AS created_by, 5 AS created_ns,"
        " 6 AS modified_ns"
    )
    record = processor_of(row)
    assert (record.twin_slug, record.spec, record.enabled) == ("rig", {"cutoff_hz": 2}, False)
    assert record.enabled is False


def test_a_twin_is_as_visible_as_its_least_private_part() -> None:
    row = {"id": 1, "slug": "rig", "dt_id": "dt:rig", "name": "Rig", "created_ns": 1,
           "modified_ns": 2}  # fmt: skip
    assert twin_of(row, ["private", "public"]).visibility == "public"
    assert twin_of(row, ["ops", "private"]).visibility == "group"
    assert twin_of(row, ["private"]).visibility == "private"
    assert twin_of(row, []).levels == []


def test_an_audit_row_keeps_its_id_and_every_field() -> None:
    entry = AuditEntry(
        10, "rig", "erp", "ada", "GET", "/x", 200, "forwarded", 0, 12, None, 2.5, id=9
    )
    row = {"id": 9, **{f: getattr(entry, f) for f in AUDIT_COLUMNS.split(", ")}}
    assert audit_of(row) == entry
