"""The privacy rules are written three times: in Python (auth.rights.may_see_level) and twice
in SQL (store.sqlite.visibility). This test holds the three to the same answers."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from twinlink.auth.rights import ANONYMOUS, Principal, may_see_level
from twinlink.domain.records import User
from twinlink.store.sqlite.db import connect, migrate
from twinlink.store.sqlite.visibility import part_visible, visible_private_parts

LEVELS = ["public", "group-1", "group-2", "private"]
ROLES = [None, "viewer", "editor", "owner"]
READERS = [
    ANONYMOUS,
    Principal(User(7, "u", False, [], 0)),
    Principal(User(7, "u", False, ["group-1"], 0)),
    Principal(User(7, "u", False, ["private", "public"], 0)),  # never granted by a group
    Principal(User(7, "u", True, [], 0)),
]


@pytest.mark.parametrize(
    "reader", READERS, ids=lambda p: repr(p.user and (p.user.groups, p.user.is_admin))
)
def test_sql_and_python_rules_agree(reader: Principal, tmp_path: Path) -> None:
    c = connect(tmp_path / "t.sqlite3")
    migrate(c)
    c.execute("INSERT INTO users(id, username, created_ns) VALUES (7, 'u', 0)")
    expected: dict[int, bool] = {}
    for twin_id, role in enumerate(ROLES, start=1):
        c.execute(
            "INSERT INTO twins(id, slug, dt_id, name, created_ns, modified_ns)"
            " VALUES (?, ?, ?, 'n', 0, 0)",
            (twin_id, f"t{twin_id}", f"urn:t{twin_id}"),
        )
        if role is not None:
            c.execute("INSERT INTO twin_roles VALUES (?, 7, ?)", (twin_id, role))
        for slot, level in enumerate(LEVELS):
            part_id = twin_id * 32 + slot
            c.execute("INSERT INTO search_parts VALUES (?, ?, ?)", (part_id, twin_id, level))
            expected[part_id] = may_see_level(reader, role if reader.user else None, level)
    where, args = part_visible(reader.visibility, "p.twin_id", "p.privacy")
    by_part_visible = {
        r[0] for r in c.execute(f"SELECT p.id FROM search_parts p WHERE {where}", args)
    }
    private_sql, private_args = visible_private_parts(reader.visibility)
    by_private_parts = {r[0] for r in c.execute(private_sql, private_args)} | {
        p
        for p in expected
        if p % 32 == 0  # slot 0: the public part, visible to everyone
    }
    allowed = {p for p, ok in expected.items() if ok}
    assert by_part_visible == allowed
    if not reader.is_admin:  # admins skip the private-parts filter altogether
        assert by_private_parts == allowed
    c.close()


def test_the_matrix_is_not_trivial() -> None:
    answers = {
        may_see_level(r, role, level)
        for r, role, level in itertools.product(READERS, ROLES, LEVELS)
    }
    assert answers == {True, False}
