from __future__ import annotations

import pytest

from twinlink.auth.rights import ANONYMOUS, Principal, has_role, may_see_level
from twinlink.domain.records import User
from twinlink.domain.slug import SLUG, slug_for, slugify
from twinlink.search.service import query_terms
from twinlink.store.sqlite.search import Highlighter, fts_phrase, match_expression


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


def test_query_terms_are_plain_words() -> None:
    assert query_terms('CAD "model" OR crane* cad') == ["cad", "model", "or", "crane"]
    assert query_terms("  ") == []
    assert query_terms("d-t.fi") == ["d", "t", "fi"]
    assert len(query_terms(" ".join(f"w{i}" for i in range(20)))) == 8


def test_fts_expression_quotes_words_and_keeps_one_letter_exact() -> None:
    assert fts_phrase('a"b') == '"a""b"*'
    assert fts_phrase("d") == '"d"'
    assert fts_phrase("cad", prefix=False) == '"cad"'
    assert match_expression(["cad", "x"]) == (
        '(({name features keywords description} : "cad"*) OR ({extra} : "cad"))'
        ' AND (({name features keywords description} : "x") OR ({extra} : "x"))'
    )


def test_highlighter_marks_prefixes_and_escapes() -> None:
    h = Highlighter(["cad", "st"])
    assert h.snippet(["Crane <b>CAD</b> store"], "") == (
        "Crane &lt;b&gt;<mark>CAD</mark>&lt;/b&gt; <mark>store</mark>"
    )
    assert h.snippet(["nothing here"], "a cadence") is None  # extra: whole words only
    assert Highlighter(["saatio"]).snippet(["Säätiö owns it"], "") == "<mark>Säätiö</mark> owns it"
    long = " ".join(f"w{i}" for i in range(30)) + " cad " + " ".join(f"v{i}" for i in range(30))
    snippet = Highlighter(["cad"]).snippet([long], "")
    assert snippet is not None and snippet.startswith("…") and snippet.endswith("…")
    assert snippet.count(" ") == 9
