from __future__ import annotations

import pytest

from twinlink.auth.rights import ANONYMOUS, Principal, has_role, may_see_level
from twinlink.domain.slug import SLUG, slug_for, slugify
from twinlink.search.service import query_terms
from twinlink.store.records import User


def user(admin: bool = False, groups: tuple[str, ...] = ()) -> Principal:
    return Principal(User(1, "u", admin, list(groups), 0))


@pytest.mark.parametrize(
    ("explicit", "iri", "dt_id", "name", "expected"),
    [
        ("given", "https://h/x", "http://d/y", "N", "given"),
        (None, "https://twins.example.org/crane-two/", "http://d/y", "N", "crane-two"),
        (None, None, "http://d-t.fi/ilmatar-K16052", "N", "ilmatar-k16052"),
        (None, None, None, "Ilmatar crane (Aalto)", "ilmatar-crane-aalto"),
        (None, None, "urn:uuid:", "Säätiö", "saatio"),
    ],
)
def test_slug_for(
    explicit: str | None, iri: str | None, dt_id: str | None, name: str, expected: str
) -> None:
    assert slug_for(explicit, iri, dt_id, name) == expected


def test_slugify_limits_length_and_charset() -> None:
    slug = slugify("A" * 100 + " b")
    assert len(slug) <= 64 and SLUG.match(slug)


@pytest.mark.parametrize(
    ("who", "role", "level", "allowed"),
    [
        (ANONYMOUS, None, "public", True),
        (ANONYMOUS, None, "group-1", False),
        (ANONYMOUS, None, "private", False),
        (user(), None, "group-1", False),
        (user(groups=("group-1",)), None, "group-1", True),
        (user(groups=("group-1",)), None, "private", False),
        (user(), "viewer", "group-1", True),
        (user(), "viewer", "private", False),
        (user(), "editor", "private", True),
        (user(), "owner", "private", True),
        (user(admin=True), None, "private", True),
    ],
)
def test_may_see_level(who: Principal, role: str | None, level: str, allowed: bool) -> None:
    assert may_see_level(who, role, level) is allowed


def test_has_role_ranks() -> None:
    assert has_role(user(), "owner", "editor")
    assert not has_role(user(), "viewer", "editor")
    assert not has_role(user(), None, "viewer")
    assert has_role(user(admin=True), None, "owner")


def test_query_terms_are_quoted_prefixes_without_fts_syntax() -> None:
    assert query_terms('CAD "model" OR crane*') == ['"cad"*', '"model"*', '"or"*', '"crane"*']
    assert query_terms("  ") == []
    assert query_terms("d-t.fi") == ['"d"', '"t"', '"fi"*']  # one letter: exact, not a prefix
    assert len(query_terms(" ".join(f"w{i}" for i in range(20)))) == 8
