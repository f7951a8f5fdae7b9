"""Relations between twins: both ends agree, no composition cycles, traversal, delete."""

from __future__ import annotations

from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    apply,
    assert_problem,
    make_user,
    twin_count,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration


class Twins:
    """Short names for a test's twins: `t.id("a")` is a unique id, `t.slug("a")` its slug."""

    def __init__(self) -> None:
        self.prefix = unique("rel")
        self.tag = self.prefix.split("-")[-1]  # a word that only this test's twins' names hold

    def slug(self, name: str) -> str:
        return f"{self.prefix}-{name}"

    def id(self, name: str) -> str:
        return f"urn:test:{self.slug(name)}"

    def doc(self, name: str, *rels: tuple[str, str], **kw: Any) -> str:
        return twin_doc(
            self.id(name),
            name=kw.pop("title", f"{name.upper()} {self.tag}"),
            relations=[(t, self.id(o)) for t, o in rels],
            **kw,
        )


def relations(c: httpx.Client, slug: str) -> set[tuple[str, str]]:
    r = c.get(f"/api/v1/twins/{slug}")
    assert r.status_code == 200, r.text
    return {(x["relationType"], x["id"]) for x in r.json()["document"].get("relations", [])}


def tree(c: httpx.Client, slug: str, direction: str, depth: int) -> dict[str, Any]:
    r = c.get(f"/api/v1/twins/{slug}/relations", params={"direction": direction, "depth": depth})
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def shape(node: dict[str, Any]) -> Any:
    """A traversal answer as nested {slug-or-id: {...}}, order-free."""
    key = node.get("slug") or f"unregistered:{node['id']}"
    return {key: {k: v for child in node["nodes"] for k, v in shape(child).items()}}


# -- both ends -----------------------------------------------------------------------------


def test_parent_declared_on_one_end_shows_as_child_on_the_other(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("b"))
        apply(admin, t.doc("a", ("parent", "b")))
        assert relations(admin, t.slug("b")) == {("child", t.id("a"))}
        assert relations(admin, t.slug("a")) == {("parent", t.id("b"))}


def test_child_declared_on_one_end_shows_as_parent_on_the_other(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("child", "b")))
        apply(admin, t.doc("b"))  # registered after the relation was declared
        assert relations(admin, t.slug("b")) == {("parent", t.id("a"))}
        assert relations(admin, t.slug("a")) == {("child", t.id("b"))}


def test_sibling_shows_on_both_ends(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("sibling", "b")), t.doc("b"))
        assert relations(admin, t.slug("a")) == {("sibling", t.id("b"))}
        assert relations(admin, t.slug("b")) == {("sibling", t.id("a"))}


def test_relation_declared_on_both_ends_is_listed_once(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("parent", "b")), t.doc("b", ("child", "a")))
        r = admin.get(f"/api/v1/twins/{t.slug('b')}").json()["document"]["relations"]
        assert r == [{"relationType": "child", "id": t.id("a")}]


def test_removing_a_relation_from_the_declaring_document_removes_it_from_the_other_end(
    server: Server,
) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("b"), t.doc("a", ("parent", "b"), ("sibling", "c")), t.doc("c"))
        assert relations(admin, t.slug("b")) == {("child", t.id("a"))}
        [result] = apply(admin, t.doc("a", ("sibling", "c"))).json()["results"]
        assert result["outcome"] == "updated"
        assert relations(admin, t.slug("b")) == set()
        assert relations(admin, t.slug("a")) == {("sibling", t.id("c"))}
        apply(admin, t.doc("a"))
        assert relations(admin, t.slug("c")) == set()
        assert relations(admin, t.slug("a")) == set()


def test_relation_stays_while_the_other_end_still_declares_it(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("parent", "b")), t.doc("b", ("child", "a")))
        apply(admin, t.doc("a"))  # a forgets it; b still declares it
        assert relations(admin, t.slug("a")) == {("parent", t.id("b"))}
        assert relations(admin, t.slug("b")) == {("child", t.id("a"))}


def test_relations_are_visible_only_at_the_privacy_level_that_declares_them(
    server: Server,
) -> None:
    t = Twins()
    with server.admin as admin:
        apply(
            admin,
            t.doc("a"),
            twin_doc(t.id("a"), privacy="private", relations=[("child", t.id("b"))]),
        )
        apply(admin, t.doc("b"))
        assert relations(admin, t.slug("b")) == {("parent", t.id("a"))}
    token = make_user(server, unique("relreader"))
    with server.client(token) as c:
        assert relations(c, t.slug("a")) == set()
        assert relations(c, t.slug("b")) == set()
        # Traversal is another way to read the same graph: it must not show the relation either.
        assert shape(tree(c, t.slug("a"), "down", 3)) == {t.slug("a"): {}}
        assert shape(tree(c, t.slug("b"), "up", 3)) == {t.slug("b"): {}}


# -- cycles --------------------------------------------------------------------------------


def test_composition_cycle_is_refused_and_nothing_is_stored(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("child", "b")))
        apply(admin, t.doc("b", ("child", "c")))
        apply(admin, t.doc("c", description="before"))
        before = admin.get(f"/api/v1/twins/{t.slug('c')}").json()
        # c declares a as its child: a -> b -> c -> a.
        r = apply(admin, t.doc("c", ("child", "a"), description="after"), expect=None)
        assert_problem(r, 409)
        after = admin.get(f"/api/v1/twins/{t.slug('c')}").json()
        assert after == before
        assert relations(admin, t.slug("a")) == {("child", t.id("b"))}
        # The same cycle declared from the other end: a names c as its parent.
        r = apply(admin, t.doc("a", ("child", "b"), ("parent", "c")), expect=None)
        assert_problem(r, 409)
        assert relations(admin, t.slug("a")) == {("child", t.id("b"))}
        assert relations(admin, t.slug("c")) == {("parent", t.id("b"))}


def test_two_twin_cycle_is_refused(server: Server) -> None:
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("a", ("parent", "b")), t.doc("b"))
        assert_problem(apply(admin, t.doc("b", ("parent", "a")), expect=None), 409)
        assert relations(admin, t.slug("b")) == {("child", t.id("a"))}


def test_self_parent_is_refused_and_not_stored(server: Server) -> None:
    t = Twins()
    before = twin_count(server)
    with server.admin as admin:
        for rel in ("parent", "child"):
            assert_problem(apply(admin, t.doc("me", (rel, "me")), expect=None), 409)
            assert_problem(admin.get(f"/api/v1/twins/{t.slug('me')}"), 404)
        apply(admin, t.doc("me"))
        assert_problem(apply(admin, t.doc("me", ("parent", "me")), expect=None), 409)
        assert relations(admin, t.slug("me")) == set()
    assert twin_count(server) == before + 1


def test_cycle_within_one_request_stores_none_of_its_twins(server: Server) -> None:
    t = Twins()
    before = twin_count(server)
    with server.admin as admin:
        r = apply(admin, t.doc("x", ("parent", "y")), t.doc("y", ("parent", "x")), expect=None)
        assert_problem(r, 409)
        assert_problem(admin.get(f"/api/v1/twins/{t.slug('x')}"), 404)
        assert_problem(admin.get(f"/api/v1/twins/{t.slug('y')}"), 404)
    assert twin_count(server) == before


# -- traversal -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def family(server: Server) -> Twins:
    """root -> c1 -> c2 -> c3 -> (an unregistered id), and root -> c1b.
    Edges are declared from either end on purpose."""
    t = Twins()
    with server.admin as admin:
        apply(
            admin,
            t.doc("root", ("child", "c1")),
            t.doc("c1b", ("parent", "root")),
            t.doc("c1", ("child", "c2")),
            t.doc("c2"),
            t.doc("c3", ("parent", "c2"), ("child", "ghost")),
        )
    return t


def test_traversal_down_is_limited_to_depth(server: Server, family: Twins) -> None:
    s = family.slug
    with server.admin as admin:
        assert shape(tree(admin, s("root"), "down", 1)) == {s("root"): {s("c1"): {}, s("c1b"): {}}}
        assert shape(tree(admin, s("root"), "down", 2)) == {
            s("root"): {s("c1"): {s("c2"): {}}, s("c1b"): {}}
        }
        assert shape(tree(admin, s("root"), "down", 3)) == {
            s("root"): {s("c1"): {s("c2"): {s("c3"): {}}}, s("c1b"): {}}
        }
        deep = tree(admin, s("root"), "down", 32)
    ghost = f"unregistered:{family.id('ghost')}"
    assert shape(deep) == {s("root"): {s("c1"): {s("c2"): {s("c3"): {ghost: {}}}}, s("c1b"): {}}}
    assert deep["id"] == family.id("root") and deep["name"] == f"ROOT {family.tag}"
    c3 = deep["nodes"][[n["slug"] for n in deep["nodes"]].index(s("c1"))]["nodes"][0]["nodes"][0]
    assert c3["nodes"] == [{"id": family.id("ghost"), "registered": False, "nodes": []}]


def test_traversal_up_returns_ancestors(server: Server, family: Twins) -> None:
    s = family.slug
    with server.admin as admin:
        assert shape(tree(admin, s("c3"), "up", 1)) == {s("c3"): {s("c2"): {}}}
        assert shape(tree(admin, s("c3"), "up", 2)) == {s("c3"): {s("c2"): {s("c1"): {}}}}
        assert shape(tree(admin, s("c3"), "up", 32)) == {
            s("c3"): {s("c2"): {s("c1"): {s("root"): {}}}}
        }
        assert shape(tree(admin, s("root"), "up", 5)) == {s("root"): {}}
        assert shape(tree(admin, s("c1b"), "down", 5)) == {s("c1b"): {}}


def test_traversal_skips_twins_the_reader_may_not_see(server: Server, family: Twins) -> None:
    s = family.slug
    hidden = f"{family.prefix}-hidden"
    with server.admin as admin:
        apply(
            admin,
            twin_doc(
                f"urn:test:{hidden}",
                name="Hidden child",
                privacy="private",
                relations=[("parent", family.id("c1b"))],
            ),
        )
        assert shape(tree(admin, s("c1b"), "down", 2)) == {s("c1b"): {hidden: {}}}
    token = make_user(server, unique("walker"))
    with server.client(token) as c:
        answer = c.get(f"/api/v1/twins/{s('c1b')}/relations", params={"depth": 2})
        assert answer.status_code == 200
        assert shape(answer.json()) == {s("c1b"): {}}
        assert "Hidden child" not in answer.text and hidden not in answer.text
        assert_problem(c.get(f"/api/v1/twins/{hidden}/relations", params={"direction": "up"}), 404)


# -- delete --------------------------------------------------------------------------------


def test_delete_refuses_while_children_are_registered_and_cascade_deletes_the_subtree(
    server: Server,
) -> None:
    t = Twins()
    with server.admin as admin:
        apply(
            admin,
            t.doc("top", ("child", "mid"), ("child", "unregistered")),
            t.doc("mid"),
            t.doc("leaf", ("parent", "mid")),
            t.doc("side", ("sibling", "top")),
            t.doc("up", ("child", "top")),
        )
        r = admin.delete(f"/api/v1/twins/{t.slug('top')}")
        body = assert_problem(r, 409)
        assert t.slug("mid") in body["detail"]
        for name in ("top", "mid", "leaf"):
            assert admin.get(f"/api/v1/twins/{t.slug(name)}").status_code == 200
        assert_problem(admin.delete(f"/api/v1/twins/{t.slug('mid')}"), 409)

        r = admin.delete(f"/api/v1/twins/{t.slug('top')}", params={"cascade": "true"})
        assert r.status_code == 200, r.text
        assert sorted(r.json()["deleted"]) == sorted(t.slug(n) for n in ("top", "mid", "leaf"))
        for name in ("top", "mid", "leaf"):
            assert_problem(admin.get(f"/api/v1/twins/{t.slug(name)}"), 404)
            assert_problem(admin.get(f"/twins/{t.slug(name)}"), 404)
        # Neither the sibling nor the parent is part of the subtree.
        for name in ("side", "up"):
            assert admin.get(f"/api/v1/twins/{t.slug(name)}").status_code == 200
        found = admin.get("/api/v1/search", params={"q": t.tag}).json()
        assert {h["slug"] for h in found["hits"]} == {t.slug("side"), t.slug("up")}


def test_cascade_needs_the_owner_role_on_every_descendant(server: Server) -> None:
    t = Twins()
    owner = make_user(server, unique("parentowner"))
    with server.client(owner) as c:
        apply(c, t.doc("p", ("child", "k")))
    with server.admin as admin:
        apply(admin, t.doc("k"))  # owned by the admin, not by the parent's owner
    with server.client(owner) as c:
        assert_problem(c.delete(f"/api/v1/twins/{t.slug('p')}", params={"cascade": "true"}), 403)
    with server.admin as admin:
        for name in ("p", "k"):
            assert admin.get(f"/api/v1/twins/{t.slug(name)}").status_code == 200


def test_deleting_a_twin_keeps_the_relations_other_documents_declare(server: Server) -> None:
    """The hall's document lists the crane as a child. Deleting the crane does not change the
    hall's document: the relation stays, now to an unregistered id (as it was before the crane
    was registered), and it is there again when the crane comes back."""
    t = Twins()
    with server.admin as admin:
        apply(admin, t.doc("hall", ("child", "crane")), t.doc("crane"))
        assert admin.delete(f"/api/v1/twins/{t.slug('crane')}").status_code == 200
        assert relations(admin, t.slug("hall")) == {("child", t.id("crane"))}
        # Re-applying the hall's unchanged document is a no-op.
        [again] = apply(admin, t.doc("hall", ("child", "crane"))).json()["results"]
        assert again["outcome"] == "unchanged"
        apply(admin, t.doc("crane"))
        assert relations(admin, t.slug("crane")) == {("parent", t.id("hall"))}
