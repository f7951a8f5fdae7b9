"""Search: ranking, prefixes, facets, keyword filter and privacy filtering."""

from __future__ import annotations

import json
from collections import defaultdict
from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    CRANE_SLUG,
    HALL_SLUG,
    ILMATAR,
    apply,
    apply_examples,
    assert_problem,
    example_documents,
    load_yaml,
    make_user,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

PUBLIC = load_yaml(ILMATAR / "ilmatar-public.yaml")


def feature_with_keyword(doc: dict[str, Any], keyword: str) -> str:
    [name] = [f["name"] for f in doc["features"] if keyword in f.get("keywords", [])]
    return str(name)


def search(c: httpx.Client, q: str = "", **params: Any) -> dict[str, Any]:
    r = c.get("/api/v1/search", params={"q": q, **params})
    assert r.status_code == 200, r.text
    body = r.json()
    scores = [h["score"] for h in body["hits"]]
    assert scores == sorted(scores, reverse=True), "hits must be ranked best first"
    return body  # type: ignore[no-any-return]


def hit(body: dict[str, Any], slug: str) -> dict[str, Any]:
    found = [h for h in body["hits"] if h["slug"] == slug]
    assert found, f"{slug} not among {[h['slug'] for h in body['hits']]}"
    return dict(found[0])


def matched_features(h: dict[str, Any]) -> set[str]:
    return {m["feature"] for m in h["matches"] if m["feature"] is not None}


@pytest.fixture(scope="module")
def examples(server: Server) -> None:
    apply_examples(server)


def test_cad_finds_the_crane_first_with_its_cad_feature(server: Server, examples: None) -> None:
    cad_feature = feature_with_keyword(PUBLIC, "CAD")
    with server.admin as admin:
        body = search(admin, "CAD")
    assert body["hits"][0]["slug"] == CRANE_SLUG
    assert body["hits"][0]["name"] == PUBLIC["name"]
    assert cad_feature in matched_features(body["hits"][0])
    assert body["total"] == len(body["hits"]) >= 1


def test_historical_finds_the_historian(server: Server, examples: None) -> None:
    historian = feature_with_keyword(PUBLIC, "historical")
    with server.admin as admin:
        exact = search(admin, "historical")
        prefix = search(admin, "histor")
        upper = search(admin, "HISTORICAL")
    assert exact["hits"][0]["slug"] == CRANE_SLUG
    assert historian in matched_features(exact["hits"][0])
    # Each word matches as a prefix, so a half-typed word finds the same feature.
    assert historian in matched_features(hit(prefix, CRANE_SLUG))
    assert [h["slug"] for h in upper["hits"]] == [h["slug"] for h in exact["hits"]]


def test_multi_word_query_matches_across_name_and_features(server: Server, examples: None) -> None:
    cad_feature = feature_with_keyword(PUBLIC, "CAD")
    with server.admin as admin:
        body = search(admin, "crane CAD")
        hall_only = search(admin, "hall")
    top = body["hits"][0]
    assert top["slug"] == CRANE_SLUG
    assert cad_feature in matched_features(top)
    # Every word must match: the hall mentions the crane but holds no CAD.
    assert HALL_SLUG in [h["slug"] for h in hall_only["hits"]]
    assert HALL_SLUG not in [h["slug"] for h in body["hits"]]


def test_matches_carry_highlighted_snippets(server: Server, examples: None) -> None:
    with server.admin as admin:
        body = search(admin, "CAD")
    snippets = [m["snippet"] for m in body["hits"][0]["matches"] if "snippet" in m]
    assert snippets and all("<mark>" in s for s in snippets)
    assert any("<mark>CAD</mark>" in s for s in snippets)


def test_name_match_outranks_a_match_in_a_feature_description(server: Server) -> None:
    word = "quokka" + unique("w").split("-")[1]
    with server.admin as admin:
        apply(
            admin,
            twin_doc(
                f"urn:test:{unique('by-desc')}",
                name="Plain station",
                description="A station.",
                features=[{"name": "Logger", "description": f"stores {word} readings"}],
            ),
            twin_doc(
                f"urn:test:{unique('by-name')}", name=f"{word} station", description="A station."
            ),
        )
        body = search(admin, word)
    assert [h["name"] for h in body["hits"]] == [f"{word} station", "Plain station"]
    assert body["hits"][0]["score"] > body["hits"][1]["score"]
    assert matched_features(body["hits"][1]) == {"Logger"}


def _example_keyword_counts() -> dict[str, int]:
    """How many example twins have a feature with each keyword (all parts, as admin sees)."""
    by_twin: dict[str, set[str]] = defaultdict(set)
    for path in example_documents():
        doc = load_yaml(path)
        for f in doc.get("features", []):
            by_twin[doc["id"]].update(f.get("keywords", []))
    counts: dict[str, int] = defaultdict(int)
    for keywords in by_twin.values():
        for k in keywords:
            counts[k] += 1
    return counts


def test_keyword_facets_count_twins(server: Server, examples: None) -> None:
    expected = _example_keyword_counts()
    with server.admin as admin:
        body = search(admin, "CAD")
        everything = search(admin, "", limit=200)
    facets = {f["value"]: f["count"] for f in body["facets"]["keywords"]}
    assert facets["CAD"] == expected["CAD"]
    # Facets describe the hits: only keywords of matched twins appear.
    crane_keywords = {k for f in PUBLIC["features"] for k in f.get("keywords", [])}
    assert set(facets) <= crane_keywords | {
        k
        for p in ILMATAR.glob("ilmatar-*.yaml")
        for f in load_yaml(p).get("features", [])
        for k in f.get("keywords", [])
    }
    all_facets = {f["value"]: f["count"] for f in everything["facets"]["keywords"]}
    shared = [k for k, n in expected.items() if n > 1]
    assert 0 < len(shared) <= 25, "the examples share a few keywords between twins"
    # Facets are ranked by count, so every shared keyword is among the first 25.
    for k in shared:
        assert all_facets.get(k) == expected[k], k
    counts = [f["count"] for f in everything["facets"]["keywords"]]
    assert counts == sorted(counts, reverse=True)


def test_keyword_filter_narrows_results(server: Server, examples: None) -> None:
    with server.admin as admin:
        broad = search(admin, "real")
        narrow = search(admin, "real", keyword="CAD")
        only_keyword = search(admin, "", keyword="CAD")
        none = search(admin, "real", keyword=unique("no-such-keyword"))
    assert len(broad["hits"]) >= 3  # "real-time" is a keyword of the crane, the hall and Tingen
    assert [h["slug"] for h in narrow["hits"]] == [CRANE_SLUG]
    assert [h["slug"] for h in only_keyword["hits"]] == [CRANE_SLUG]
    assert none["hits"] == [] and none["total"] == 0


def test_pagination(server: Server, examples: None) -> None:
    with server.admin as admin:
        full = search(admin, "data", limit=200)
        assert full["total"] >= 2
        pages = [search(admin, "data", limit=1, offset=i)["hits"] for i in range(full["total"])]
    assert [p[0]["slug"] for p in pages] == [h["slug"] for h in full["hits"]]


# -- privacy -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def secretive(server: Server) -> dict[str, str]:
    """A twin whose private part alone holds a feature with a unique word and keyword."""
    tag = unique("s").split("-")[1]
    words = {
        "public_word": f"openword{tag}",
        "secret_word": f"hushword{tag}",
        "secret_feature": f"Vault {tag}",
        "secret_keyword": f"kw{tag}",
        "slug": f"secretive-{tag}",
    }
    dt_id = f"urn:test:{words['slug']}"
    with server.admin as admin:
        apply(
            admin,
            twin_doc(
                dt_id,
                name=f"Secretive {words['public_word']}",
                features=[{"name": "Open door", "description": "anyone may read"}],
            ),
            twin_doc(
                dt_id,
                privacy="private",
                features=[
                    {
                        "name": words["secret_feature"],
                        "description": f"holds the {words['secret_word']} archive",
                        "keywords": [words["secret_keyword"]],
                    }
                ],
            ),
        )
    editor, viewer = unique("sed"), unique("svw")
    words["editor"] = make_user(server, editor)
    words["viewer"] = make_user(server, viewer)
    words["plain"] = make_user(server, unique("splain"))
    with server.admin as admin:
        for who, role in ((editor, "editor"), (viewer, "viewer")):
            r = admin.put(f"/api/v1/twins/{words['slug']}/roles/{who}", json={"role": role})
            assert r.status_code == 200, r.text
    return words


def test_private_feature_is_found_by_an_editor(server: Server, secretive: dict[str, str]) -> None:
    with server.client(secretive["editor"]) as c:
        body = search(c, secretive["secret_word"])
        by_keyword = search(c, "", keyword=secretive["secret_keyword"])
    [h] = body["hits"]
    assert h["slug"] == secretive["slug"]
    assert matched_features(h) == {secretive["secret_feature"]}
    assert [m["privacy"] for m in h["matches"]] == ["private"]
    assert [x["slug"] for x in by_keyword["hits"]] == [secretive["slug"]]


@pytest.mark.parametrize("who", ["plain", "viewer"])
def test_private_feature_is_not_found_without_the_right(
    server: Server, secretive: dict[str, str], who: str
) -> None:
    with server.client(secretive[who]) as c:
        secret = c.get("/api/v1/search", params={"q": secretive["secret_word"]})
        by_keyword = c.get("/api/v1/search", params={"keyword": secretive["secret_keyword"]})
        public = c.get("/api/v1/search", params={"q": secretive["public_word"]})
        # The secret word and the public word together: must not match through the private part.
        both = c.get(
            "/api/v1/search", params={"q": f"{secretive['public_word']} {secretive['secret_word']}"}
        )
    assert secret.json()["hits"] == [] and secret.json()["total"] == 0
    assert by_keyword.json()["hits"] == []
    assert both.json()["hits"] == []
    # The twin is found by its public word, and the hit shows nothing of the private part.
    assert [h["slug"] for h in public.json()["hits"]] == [secretive["slug"]]
    for r in (secret, by_keyword, public, both):
        assert r.status_code == 200
        # Everything but the echo of the caller's own query.
        answer = json.dumps({k: v for k, v in r.json().items() if k not in ("query", "keyword")})
        for hidden in ("secret_feature", "secret_word", "secret_keyword"):
            assert secretive[hidden] not in answer, (who, hidden, answer[:500])


def test_group_part_is_searchable_by_group_members_only(server: Server, examples: None) -> None:
    group = load_yaml(ILMATAR / "ilmatar-group.yaml")
    public_names = {f["name"] for f in PUBLIC["features"]}
    [group_feature] = [f for f in group["features"] if f["name"] not in public_names]
    word = group_feature["keywords"][0]
    member = make_user(server, unique("member"), groups=[group["privacy"]])
    outsider = make_user(server, unique("outsider"), groups=["some-other-group"])
    with server.client(member) as c:
        found = search(c, word)
    assert group_feature["name"] in matched_features(hit(found, CRANE_SLUG))
    with server.client(outsider) as c:
        r = c.get("/api/v1/search", params={"q": word})
    assert group_feature["name"] not in r.text
    assert CRANE_SLUG not in [h["slug"] for h in r.json()["hits"]]


def test_search_needs_a_token(server: Server) -> None:
    with server.client() as anon:
        assert_problem(anon.get("/api/v1/search", params={"q": "crane"}), 401)


@pytest.mark.parametrize(
    "q",
    [
        '"',
        "*",
        "NOT",
        "a AND b OR",
        "(",
        ")",
        "^x",
        "_",
        "__init__",
        "NEAR(a b)",
        "name:crane",
        "'",
        "\\",
        "-crane",
        "crane*",
        "😀",
        "Åland ÄÖ",
        "a" * 256,
        " ",
    ],
)
def test_query_syntax_characters_never_break_search(server: Server, examples: None, q: str) -> None:
    with server.admin as admin:
        r = admin.get("/api/v1/search", params={"q": q})
    assert r.status_code == 200, r.text
    assert isinstance(r.json()["hits"], list)


def test_the_id_is_searchable_and_one_letter_is_no_wildcard(server: Server) -> None:
    apply_examples(server)
    with server.admin as admin:
        hits = admin.get("/api/v1/search", params={"q": "K16052"}).json()["hits"]
        assert [h["slug"] for h in hits] == [CRANE_SLUG]
        every = admin.get("/api/v1/search", params={"q": "", "limit": 200}).json()["total"]
        one_letter = admin.get("/api/v1/search", params={"q": "q"}).json()["total"]
    assert one_letter < every
