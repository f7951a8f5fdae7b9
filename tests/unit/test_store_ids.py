"""Twin and device ids are never handed out twice (history.db keys on them)."""

from __future__ import annotations

from pathlib import Path

from twinlink.store.sqlite.db import connect, migrate, next_id


def test_an_id_is_not_reused_after_the_largest_is_deleted(tmp_path: Path) -> None:
    conn = connect(tmp_path / "meta.sqlite3")
    try:
        migrate(conn)
        first, second = next_id(conn, "twins"), next_id(conn, "twins")
        for twin_id in (first, second):
            conn.execute(
                "INSERT INTO twins(id, slug, dt_id, name, created_ns, modified_ns)"
                " VALUES (?, ?, ?, '', 0, 0)",
                (twin_id, f"t{twin_id}", f"urn:t{twin_id}"),
            )
        conn.execute("DELETE FROM twins WHERE id = ?", (second,))
        assert next_id(conn, "twins") == second + 1
        assert next_id(conn, "devices") == 1
    finally:
        conn.close()


def test_the_counters_start_above_existing_rows(tmp_path: Path) -> None:
    conn = connect(tmp_path / "meta.sqlite3")
    try:
        migrate(conn, target=3)  # a data dir from before migration 0004
        conn.execute(
            "INSERT INTO twins(id, slug, dt_id, name, created_ns, modified_ns)"
            " VALUES (41, 'old', 'urn:old', '', 0, 0)"
        )
        migrate(conn)
        assert next_id(conn, "twins") == 42
    finally:
        conn.close()
