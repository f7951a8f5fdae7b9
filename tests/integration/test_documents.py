"""DT documents over HTTP: idempotent apply, privacy parts, content negotiation, bad input."""

from __future__ import annotations

import html
import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
import yaml

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import (
    CRANE_SLUG,
    ILMATAR,
    PROBLEM,
    YAML_HEADERS,
    apply,
    assert_problem,
    last_error,
    load_yaml,
    make_user,
    twin_count,
    twin_doc,
    unhandled_errors,
    unique,
    wait_for_clock_past,
)

JSON_HEADERS = {"Content-Type": "application/json"}


def get_doc(c: httpx.Client, slug: str) -> dict[str, Any]:
    r = c.get(f"/api/v1/twins/{slug}")
    assert r.status_code == 200, r.text
    return r.json()["document"]  # type: ignore[no-any-return]


def slug_of(r: httpx.Response) -> str:
    return str(r.json()["results"][0]["slug"])


# -- idempotent apply ----------------------------------------------------------------------


def test_apply_twice_is_unchanged_and_a_change_is_an_update(server: Server) -> None:
    dt_id = f"urn:test:{unique('idem')}"
    features = [{"name": "Logger", "description": "logs things", "keywords": ["log"]}]
    first = twin_doc(dt_id, name="Idempotent twin", description="v1", features=features)
    with server.admin as admin:
        r1 = apply(admin, first)
        [created] = r1.json()["results"]
        assert created["outcome"] == "created"
        assert created["levels"] == ["public"]
        slug = created["slug"]
        doc1 = get_doc(admin, slug)
        assert doc1["createdMachine"] == doc1["modifiedMachine"]

        # A later apply of the same text must not touch the twin, however much time passed.
        wait_for_clock_past(doc1["modifiedHuman"])
        [again] = apply(admin, first).json()["results"]
        assert again["outcome"] == "unchanged"
        assert again["modified"] == created["modified"]
        doc2 = get_doc(admin, slug)
        for key in ("createdMachine", "createdHuman", "modifiedMachine", "modifiedHuman"):
            assert doc2[key] == doc1[key], key

        wait_for_clock_past(doc1["modifiedHuman"])
        changed = twin_doc(dt_id, name="Idempotent twin", description="v2", features=features)
        [updated] = apply(admin, changed).json()["results"]
        assert updated["outcome"] == "updated"
        assert updated["slug"] == slug
        doc3 = get_doc(admin, slug)
        assert doc3["description"] == "v2"
        assert doc3["modifiedHuman"] > doc1["modifiedHuman"]
        assert int(doc3["modifiedMachine"]) >= int(doc1["modifiedMachine"])
        assert doc3["createdMachine"] == doc1["createdMachine"]
        assert doc3["createdHuman"] == doc1["createdHuman"]

        [third] = apply(admin, changed).json()["results"]
        assert third["outcome"] == "unchanged"


def test_platform_timestamps_in_a_document_are_not_taken_as_modified(server: Server) -> None:
    dt_id = f"urn:test:{unique('stamps')}"
    body = twin_doc(
        dt_id, name="Stamped", modifiedMachine="1", modifiedHuman="1970-01-01T00:00:01Z"
    )
    with server.admin as admin:
        slug = slug_of(apply(admin, body))
        doc = get_doc(admin, slug)
    # The platform keeps modification times; a document cannot claim 1970.
    assert doc["modifiedMachine"] != "1"
    assert not doc["modifiedHuman"].startswith("1970")


# -- privacy parts -------------------------------------------------------------------------


@dataclass
class Crane:
    public: dict[str, Any]
    group: dict[str, Any]
    private: dict[str, Any]
    tokens: dict[str, str]  # who -> token

    @property
    def group_only_features(self) -> list[str]:
        public_names = {f["name"] for f in self.public["features"]}
        return [f["name"] for f in self.group["features"] if f["name"] not in public_names]

    @property
    def private_texts(self) -> list[str]:
        return [f["requirement"] for f in self.private["features"]]


@pytest.fixture(scope="module")
def crane(server: Server) -> Crane:
    """The Ilmatar crane applied part by part, the group part first and the public part last."""
    public = load_yaml(ILMATAR / "ilmatar-public.yaml")
    group = load_yaml(ILMATAR / "ilmatar-group.yaml")
    private = load_yaml(ILMATAR / "ilmatar-private.yaml")
    outcomes = []
    with server.admin as admin:
        for name in ("ilmatar-group.yaml", "ilmatar-private.yaml", "ilmatar-public.yaml"):
            r = admin.post(
                "/api/v1/apply", content=(ILMATAR / name).read_bytes(), headers=YAML_HEADERS
            )
            assert r.status_code == 200, r.text
            [result] = r.json()["results"]
            assert result["slug"] == CRANE_SLUG
            outcomes.append(result["outcome"])
        assert outcomes == ["created", "updated", "updated"]
        assert result["levels"] == sorted(["public", group["privacy"], "private"])
        assert result["name"] == public["name"]
    tokens = {
        "group": make_user(server, unique("grp"), groups=[group["privacy"]]),
        "other-group": make_user(server, unique("grp2"), groups=["group-2"]),
        "editor": make_user(server, editor := unique("ed")),
        "viewer": make_user(server, viewer := unique("vw")),
        "plain": make_user(server, unique("plain")),
    }
    with server.admin as admin:
        for username, role in ((editor, "editor"), (viewer, "viewer")):
            r = admin.put(f"/api/v1/twins/{CRANE_SLUG}/roles/{username}", json={"role": role})
            assert r.status_code == 200, r.text
    return Crane(public, group, private, tokens)


def _canonical_json(client: httpx.Client) -> dict[str, Any]:
    r = client.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "application/json"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("application/json")
    return r.json()  # type: ignore[no-any-return]


def _feature(doc: dict[str, Any], name: str) -> dict[str, Any]:
    [found] = [f for f in doc.get("features", []) if f["name"] == name]
    return dict(found)


def _assert_public_only(doc: dict[str, Any], crane: Crane) -> None:
    text = json.dumps(doc)
    assert doc["name"] == crane.public["name"]
    assert doc["id"] == crane.public["id"]
    assert doc["privacy"] == "public"
    assert doc["contact"] == crane.public["contact"]
    assert [f["name"] for f in doc["features"]] == [f["name"] for f in crane.public["features"]]
    for secret in crane.private_texts:
        assert secret not in text
    for name in crane.group_only_features:
        assert name not in text
    assert crane.group["contact"]["name"] not in text


def test_anonymous_sees_only_the_public_part(server: Server, crane: Crane) -> None:
    with server.client() as anon:
        doc = _canonical_json(anon)
        _assert_public_only(doc, crane)
        as_yaml = anon.get(f"/twins/{CRANE_SLUG}/index.yaml")
        for secret in crane.private_texts:
            assert secret not in as_yaml.text
        as_html = anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "text/html"})
        assert crane.group["contact"]["name"] not in as_html.text
        for name in crane.group_only_features:
            assert html.escape(name) not in as_html.text


def test_signed_in_user_without_role_or_group_sees_only_public(
    server: Server, crane: Crane
) -> None:
    for who in ("plain", "other-group"):
        with server.client(crane.tokens[who]) as c:
            _assert_public_only(_canonical_json(c), crane)
            api = c.get(f"/api/v1/twins/{CRANE_SLUG}")
            assert api.json()["levels"] == ["public"]
            _assert_public_only(api.json()["document"], crane)
            assert_problem(c.get(f"/api/v1/twins/{CRANE_SLUG}/parts/private"), 404)
            assert_problem(c.get(f"/api/v1/twins/{CRANE_SLUG}/parts/{crane.group['privacy']}"), 404)


def test_group_member_sees_the_group_part_merged(server: Server, crane: Crane) -> None:
    with server.client(crane.tokens["group"]) as c:
        doc = _canonical_json(c)
        api = c.get(f"/api/v1/twins/{CRANE_SLUG}").json()
    text = json.dumps(doc)
    assert doc["name"] == crane.public["name"]
    # The group's contact and street address override the public ones.
    assert doc["contact"] == crane.group["contact"]
    assert doc["location"]["streetAddress"] == crane.group["location"]["streetAddress"]
    assert crane.public["contact"]["name"] not in text
    # Group-only features are added; public features are kept and extended by name.
    names = [f["name"] for f in doc["features"]]
    assert names[: len(crane.public["features"])] == [f["name"] for f in crane.public["features"]]
    for name in crane.group_only_features:
        assert name in names
    for gf in crane.group["features"]:
        merged = _feature(doc, gf["name"])
        for key, value in gf.items():
            assert merged[key] == value, (gf["name"], key)
        pub = [f for f in crane.public["features"] if f["name"] == gf["name"]]
        if pub:
            assert merged["description"] == pub[0]["description"]
    for secret in crane.private_texts:
        assert secret not in text
    assert api["levels"] == sorted(["public", crane.group["privacy"]])
    assert doc["privacy"] == crane.group["privacy"]


def test_editor_sees_private_content(server: Server, crane: Crane) -> None:
    with server.client(crane.tokens["editor"]) as c:
        doc = _canonical_json(c)
        api = c.get(f"/api/v1/twins/{CRANE_SLUG}").json()
        part = c.get(f"/api/v1/twins/{CRANE_SLUG}/parts/private")
    assert api["role"] == "editor"
    assert api["levels"] == sorted(["public", crane.group["privacy"], "private"])
    for pf in crane.private["features"]:
        # The most private value wins.
        assert _feature(doc, pf["name"])["requirement"] == pf["requirement"]
    for name in crane.group_only_features:
        assert name in [f["name"] for f in doc["features"]]
    assert doc["privacy"] == "private"
    assert part.status_code == 200
    assert part.json()["features"] == crane.private["features"]


def test_viewer_does_not_see_private_content(server: Server, crane: Crane) -> None:
    with server.client(crane.tokens["viewer"]) as c:
        doc = _canonical_json(c)
        api = c.get(f"/api/v1/twins/{CRANE_SLUG}").json()
        assert_problem(c.get(f"/api/v1/twins/{CRANE_SLUG}/parts/private"), 404)
    text = json.dumps(doc)
    for secret in crane.private_texts:
        assert secret not in text
    assert "private" not in api["levels"]
    # A role on the twin opens its group parts (auth/rights.py).
    assert crane.group["privacy"] in api["levels"]
    assert doc["contact"] == crane.group["contact"]


def test_parts_merge_the_same_whatever_order_they_arrive_in(server: Server, crane: Crane) -> None:
    """The three crane files under a new id, in one stream, most private first."""
    new_id = f"urn:test:{unique('crane-copy')}"
    texts = [
        (ILMATAR / name).read_text("utf-8").replace(crane.public["id"], new_id)
        for name in ("ilmatar-private.yaml", "ilmatar-group.yaml", "ilmatar-public.yaml")
    ]
    with server.admin as admin:
        [result] = apply(admin, *texts).json()["results"]
        assert result["outcome"] == "created"
        copy = get_doc(admin, result["slug"])
        original = get_doc(admin, CRANE_SLUG)
    volatile = {
        "id",
        "hosting-iri",
        "createdMachine",
        "createdHuman",
        "modifiedMachine",
        "modifiedHuman",
        "relations",
    }
    assert {k: v for k, v in copy.items() if k not in volatile} == {
        k: v for k, v in original.items() if k not in volatile
    }
    assert list(copy) == list(original)  # and the same key order


def test_twin_name_from_a_private_part_does_not_leak(server: Server) -> None:
    """A twin whose public part has no name takes its listed name from a part the reader may not
    see; lists, search hits and the index page must not show it to such readers."""
    secret_name = f"Codename {unique('zebra')}"
    dt_id = f"urn:test:{unique('nameless')}"
    with server.admin as admin:
        r = apply(
            admin,
            twin_doc(dt_id, description="A public description"),
            twin_doc(dt_id, privacy="private", name=secret_name),
        )
        slug = slug_of(r)
    token = make_user(server, unique("reader"))
    with server.client(token) as c:
        listed = c.get("/api/v1/twins", params={"limit": 500})
        one = c.get(f"/api/v1/twins/{slug}")
        found = c.get("/api/v1/search", params={"q": "public description"})
    with server.client() as anon:
        index = anon.get("/")
        page = anon.get(f"/twins/{slug}", headers={"Accept": "text/html"})
    assert slug in listed.text and slug in found.text and slug in index.text
    for r in (listed, one, found, index, page):
        assert r.status_code == 200
        assert secret_name not in r.text, f"{r.request.url}: the private name leaked"


# -- unknown keys --------------------------------------------------------------------------


def test_unknown_keys_round_trip(server: Server) -> None:
    dt_id = f"urn:test:{unique('custom')}"
    custom_top: dict[str, Any] = {
        "maintenance": {
            "window": "Sundays 02-04",
            "crew": ["a", "b"],
            "cost": 12.5,
            "urgent": False,
            "notes": None,
        }
    }
    custom_feature = {"dataRetention": "5 years", "sampling": {"rate": 100, "unit": "Hz"}}
    features = [{"name": "Store", "description": "keeps data", **custom_feature}]
    body = twin_doc(dt_id, name="Custom keys", features=features, **custom_top)
    with server.admin as admin:
        slug = slug_of(apply(admin, body))
        doc = get_doc(admin, slug)
        as_yaml = yaml.safe_load(admin.get(f"/twins/{slug}/index.yaml").text)
        as_json = admin.get(f"/twins/{slug}/index.json").json()
        stored = admin.get(f"/api/v1/twins/{slug}/parts/public").json()
    for got in (doc, as_yaml, as_json):
        assert got["maintenance"] == custom_top["maintenance"]
        feature = _feature(got, "Store")
        for key, value in custom_feature.items():
            assert feature[key] == value
        assert list(feature) == ["name", "description", *custom_feature]
    assert stored["maintenance"] == custom_top["maintenance"]


def test_example_custom_feature_key_comes_back(server: Server, crane: Crane) -> None:
    public_features = {f["name"]: f for f in crane.public["features"]}
    custom = {
        (name, key): value
        for name, f in public_features.items()
        for key, value in f.items()
        if key
        not in (
            "name",
            "description",
            "address",
            "apiAddress",
            "requirement",
            "documentation",
            "keywords",
        )
    }
    assert custom, "the public crane example should show a custom feature key"
    with server.client() as anon:
        doc = _canonical_json(anon)
    for (name, key), value in custom.items():
        assert _feature(doc, name)[key] == value


# -- the canonical URL ---------------------------------------------------------------------


def test_content_negotiation_on_the_canonical_url(server: Server, crane: Crane) -> None:
    with server.client() as anon:
        y = anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "application/yaml"})
        assert y.status_code == 200
        assert y.headers["content-type"].startswith("application/yaml")
        assert yaml.safe_load(y.text)["id"] == crane.public["id"]

        j = anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "application/json"})
        assert j.headers["content-type"].startswith("application/json")
        assert j.json()["id"] == crane.public["id"]
        assert j.json() == yaml.safe_load(y.text)

        h = anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "text/html"})
        assert h.headers["content-type"].startswith("text/html")
        assert html.escape(crane.public["name"]) in h.text
        assert h.text.lstrip().lower().startswith("<!doctype html")

        browser = "text/html,application/xhtml+xml,application/xml;q=0.9,*/*;q=0.8"
        assert (
            anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": browser})
            .headers["content-type"]
            .startswith("text/html")
        )
        ranked = "application/json;q=0.5, application/yaml;q=0.9"
        assert (
            anon.get(f"/twins/{CRANE_SLUG}", headers={"Accept": ranked})
            .headers["content-type"]
            .startswith("application/yaml")
        )
        # Fixed-format URLs ignore Accept.
        fixed_json = anon.get(f"/twins/{CRANE_SLUG}/index.json", headers={"Accept": "text/html"})
        assert fixed_json.headers["content-type"].startswith("application/json")
        fixed_yaml = anon.get(f"/twins/{CRANE_SLUG}/index.yaml", headers={"Accept": "text/html"})
        assert fixed_yaml.headers["content-type"].startswith("application/yaml")
        assert yaml.safe_load(fixed_yaml.text) == j.json()

        # The canonical link and caching: public answers to anonymous readers may be shared.
        with server.admin as admin:
            url = admin.get(f"/api/v1/twins/{CRANE_SLUG}").json()["url"]
        assert f"<{url}>" in j.headers["link"] and 'rel="canonical"' in j.headers["link"]
        assert "accept" in j.headers["vary"].lower()
        assert "private" not in j.headers.get("cache-control", "")
    with server.client(crane.tokens["editor"]) as c:
        signed_in = c.get(f"/twins/{CRANE_SLUG}", headers={"Accept": "application/json"})
    assert "no-store" in signed_in.headers["cache-control"]
    assert "private" in signed_in.headers["cache-control"]


def test_html_escapes_document_values(server: Server) -> None:
    evil = "<script>alert(1)</script>"
    dt_id = f"urn:test:{unique('xss')}"
    body = twin_doc(
        dt_id,
        name=evil,
        description='"><img src=x onerror=alert(2)>',
        homepage="javascript:alert(3)",
        features=[
            {
                "name": "<b>bold</b>",
                "keywords": ["<i>kw</i>"],
                "documentation": "javascript:alert(4)",
            }
        ],
    )
    with server.admin as admin:
        slug = slug_of(apply(admin, body))
    with server.client() as anon:
        page = anon.get(f"/twins/{slug}", headers={"Accept": "text/html"})
        index = anon.get("/")
    assert page.status_code == 200
    for text in (page.text, index.text):
        assert evil not in text
        assert html.escape(evil) in text
    assert "<img src=x" not in page.text
    assert "<b>bold</b>" not in page.text and "<i>kw</i>" not in page.text
    assert 'href="javascript:' not in page.text.lower()


# -- bad documents -------------------------------------------------------------------------


def test_malformed_yaml_names_the_line_and_stores_nothing(server: Server) -> None:
    lines = [
        'version: "1.0"',
        "privacy: public",
        f"id: urn:test:{unique('broken')}",
        "name: Broken",
        "description: fine so far",
        "  oops: a key indented under a plain value",  # line 6: "mapping values not allowed"
        "features: []",
    ]
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    assert body["errors"][0]["line"] == 6
    assert "line 6" in body["detail"]
    assert twin_count(server) == before


def test_all_schema_problems_are_reported_at_once_with_lines(server: Server) -> None:
    lines = [
        'version: "1.0"',
        "privacy: public",
        f"id: urn:test:{unique('multi')}",
        "name: Several problems",
        "relations:",
        "  - relationType: cousin",  # line 6: not parent/child/sibling
        "    id: urn:test:other",
        "features:",
        "  - name: Good",
        "  - description: a feature without a name",  # line 10: name missing
        "    keywords: [x]",
    ]
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    found = {(e["path"], e["line"]) for e in body["errors"]}
    assert ("relations[0].relationType", 6) in found
    assert any(path.startswith("features[1]") and line == 10 for path, line in found), found
    assert twin_count(server) == before


def test_rule_problems_are_reported_together_with_type_problems(server: Server) -> None:
    """An unsupported version and a duplicate feature name are problems too; they must not wait
    until the type problems elsewhere in the document are fixed."""
    lines = [
        'version: "9.9"',  # line 1: unsupported version
        "privacy: public",
        f"id: urn:test:{unique('rules')}",
        "name: Rules and types",
        "relations:",
        "  - relationType: cousin",  # line 6
        "    id: urn:test:other",
        "features:",
        "  - name: Twice",
        "  - name: Twice",  # line 10: duplicate name
    ]
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    lines_reported = {e["line"] for e in body["errors"]}
    assert {1, 6, 10} <= lines_reported, body["errors"]


def test_stream_with_an_invalid_second_document_stores_nothing(server: Server) -> None:
    first_id, second_id = f"urn:test:{unique('s1')}", f"urn:test:{unique('s2')}"
    first = twin_doc(first_id, name="First of two")
    second = twin_doc(second_id, name="Second of two", relations=[("uncle", first_id)])
    stream = first + "---\n" + second
    bad_line = stream.splitlines().index("- relationType: uncle") + 1
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=stream.encode(), headers=YAML_HEADERS)
        body = assert_problem(r, 422)
        [error] = body["errors"]
        assert error["document"] == 1
        assert error["line"] == bad_line
        assert twin_count(server) == before
        listed = admin.get("/api/v1/twins", params={"q": "of two"}).json()["items"]
    assert listed == []


def test_json_body_works_for_apply(server: Server) -> None:
    dt_id = f"urn:test:{unique('json')}"
    doc = {
        "version": "1.0",
        "privacy": "public",
        "id": dt_id,
        "name": "From JSON",
        "features": [{"name": "API", "keywords": ["json"]}],
    }
    private = {
        "version": "1.0",
        "privacy": "private",
        "id": dt_id,
        "features": [{"name": "API", "requirement": "json-secret"}],
    }
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=json.dumps(doc).encode(), headers=JSON_HEADERS)
        assert r.status_code == 200, r.text
        [result] = r.json()["results"]
        assert result["outcome"] == "created"
        slug = result["slug"]
        # A JSON list holds several documents: here the two parts of one twin.
        r = admin.post(
            "/api/v1/apply", content=json.dumps([doc, private]).encode(), headers=JSON_HEADERS
        )
        assert r.status_code == 200, r.text
        assert r.json()["results"][0]["levels"] == ["private", "public"]
        merged = get_doc(admin, slug)
        assert merged["name"] == "From JSON"
        assert _feature(merged, "API") == {
            "name": "API",
            "keywords": ["json"],
            "requirement": "json-secret",
        }
        bad = admin.post(
            "/api/v1/apply", content=b'{\n  "version": "1.0",\n  "name": }', headers=JSON_HEADERS
        )
    body = assert_problem(bad, 422)
    assert body["errors"][0]["line"] == 3


def test_create_of_an_existing_twin_is_409(server: Server) -> None:
    dt_id = f"urn:test:{unique('dup')}"
    body = twin_doc(dt_id, name="Created once").encode()
    with server.admin as admin:
        r = admin.post("/api/v1/twins", content=body, headers=YAML_HEADERS)
        assert r.status_code == 201, r.text
        assert r.json()["outcome"] == "created"
        slug = r.json()["slug"]
        assert_problem(admin.post("/api/v1/twins", content=body, headers=YAML_HEADERS), 409)
        # Another twin asking for a slug that is taken.
        other = twin_doc(f"urn:test:{unique('dup2')}", name="Other").encode()
        assert_problem(
            admin.post("/api/v1/twins", params={"slug": slug}, content=other, headers=YAML_HEADERS),
            409,
        )
        assert get_doc(admin, slug)["name"] == "Created once"


def test_put_to_a_missing_twin_is_404_and_to_another_twins_slug_is_409(server: Server) -> None:
    with server.admin as admin:
        slug = slug_of(apply(admin, twin_doc(f"urn:test:{unique('put')}", name="Put target")))
        other = twin_doc(f"urn:test:{unique('put2')}", name="Other twin").encode()
        assert_problem(
            admin.put(f"/api/v1/twins/{unique('nothing')}", content=other, headers=YAML_HEADERS),
            404,
        )
        assert_problem(admin.put(f"/api/v1/twins/{slug}", content=other, headers=YAML_HEADERS), 409)
        assert get_doc(admin, slug)["name"] == "Put target"


@pytest.fixture(scope="module")
def small_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(
        tmp_path_factory.mktemp("small"), extra_env={"TWINLINK_MAX_DOCUMENT_BYTES": "2000"}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


def _sized(n: int) -> bytes:
    head = f'version: "1.0"\nprivacy: public\nid: urn:test:sized-{n}\nname: Sized\nfiller: "'
    body = head + "x" * (n - len(head) - 2) + '"\n'
    assert len(body.encode()) == n
    return body.encode()


def test_document_size_limit(small_server: Server) -> None:
    with small_server.admin as admin:
        assert (
            admin.post("/api/v1/apply", content=_sized(2000), headers=YAML_HEADERS).status_code
            == 200
        )
        body = assert_problem(
            admin.post("/api/v1/apply", content=_sized(2001), headers=YAML_HEADERS), 413
        )
        assert "2000" in body["detail"]
        assert_problem(admin.post("/api/v1/twins", content=_sized(2001), headers=YAML_HEADERS), 413)
        assert_problem(
            admin.put("/api/v1/twins/sized-2000", content=_sized(2001), headers=YAML_HEADERS), 413
        )
        too_big_json = json.dumps({"version": "1.0", "name": "J", "pad": "y" * 2100}).encode()
        assert_problem(admin.post("/api/v1/apply", content=too_big_json, headers=JSON_HEADERS), 413)

    def chunks() -> Iterator[bytes]:  # no Content-Length: the limit must hold anyway
        data = _sized(4000)
        yield data[:1500]
        yield data[1500:]

    with small_server.admin as admin:
        assert_problem(admin.post("/api/v1/apply", content=chunks(), headers=YAML_HEADERS), 413)
        names = [t["slug"] for t in admin.get("/api/v1/twins").json()["items"]]
    assert names == ["sized-2000"]


# -- nothing answers 500 ---------------------------------------------------------------------


def _deep(levels: int) -> str:
    return 'version: "1.0"\nprivacy: public\nid: urn:test:deep\nname: Deep\nx: ' + (
        "[" * levels + "]" * levels + "\n"
    )


BILLION_LAUGHS = (
    'version: "1.0"\nprivacy: public\nid: urn:test:laughs\nname: Laughs\n'
    "a: &a [x, x, x, x, x, x, x, x, x, x]\n"
    + "".join(
        f"{n}: &{n} [{', '.join([f'*{p}'] * 10)}]\n" for p, n in zip("abcde", "bcdef", strict=True)
    )
)

BAD_DOCUMENTS: dict[str, tuple[bytes, str]] = {
    "broken yaml": (b"version: '1.0'\nname: [unclosed\n", "application/yaml"),
    "not a mapping": (b"- just\n- a list\n", "application/yaml"),
    "scalar": (b"hello\n", "application/yaml"),
    "empty": (b"", "application/yaml"),
    "only comments": (b"# nothing here\n", "application/yaml"),
    "not utf-8": (b"\xff\xfe\x00v", "application/yaml"),
    "bad json": (b'{"version": ', "application/json"),
    "json scalar": (b"42", "application/json"),
    "json list of scalars": (b"[1, 2]", "application/json"),
    "no version": (b"privacy: public\nname: x\n", "application/yaml"),
    "unsupported version": (b"version: '7'\nprivacy: public\nname: x\n", "application/yaml"),
    "bad privacy": (b"version: '1.0'\nprivacy: 'a b'\nname: x\n", "application/yaml"),
    "no id nor name": (b"version: '1.0'\nprivacy: public\n", "application/yaml"),
    "id is a list": (b"version: '1.0'\nprivacy: public\nid: [1]\n", "application/yaml"),
    "features not a list": (
        b"version: '1.0'\nprivacy: public\nname: x\nfeatures: 3\n",
        "application/yaml",
    ),
    "non-text key": (b"version: '1.0'\nprivacy: public\nname: x\n123: y\n", "application/yaml"),
    "not a number": (b"version: '1.0'\nprivacy: public\nname: x\nv: .nan\n", "application/yaml"),
    "integer beyond 64 bits": (
        b"version: '1.0'\nprivacy: public\nname: bigint\nbig: 123456789012345678901234567890\n",
        "application/yaml",
    ),
    "slug is a list": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: [1]\n",
        "application/yaml",
    ),
    "slug is a mapping": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: {a: 1}\n",
        "application/yaml",
    ),
    "bad slug": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: Not A Slug\n",
        "application/yaml",
    ),
    "nested 100 deep": (_deep(100).encode(), "application/yaml"),
    "nested 300 deep": (_deep(300).encode(), "application/yaml"),
    "nested 5000 deep": (_deep(5000).encode(), "application/yaml"),
    "json nested 5000 deep": (
        b'{"version": "1.0", "x": ' + b"[" * 5000 + b"]" * 5000 + b"}",
        "application/json",
    ),
    "billion laughs": (BILLION_LAUGHS.encode(), "application/yaml"),
    "two public parts": (
        (
            twin_doc("urn:test:twice", name="a") + "---\n" + twin_doc("urn:test:twice", name="b")
        ).encode(),
        "application/yaml",
    ),
    "self parent": (
        twin_doc(
            "urn:test:selfish", name="Selfish", relations=[("parent", "urn:test:selfish")]
        ).encode(),
        "application/yaml",
    ),
}


# Unusual but not necessarily wrong: storing them (losslessly) or refusing them are both fine.
MAY_BE_ACCEPTED = {"nested 100 deep", "nested 300 deep", "integer beyond 64 bits"}
# PUT names the twin by its URL, so a document without an id or name (or with its own `slug`,
# which the URL overrides) is a fine update there.
PUT_MAY_ACCEPT = {"no id nor name", "bad slug", "slug is a list", "slug is a mapping"}


@pytest.fixture(scope="module")
def put_target(server: Server) -> str:
    with server.admin as admin:
        return slug_of(apply(admin, twin_doc(f"urn:test:{unique('target')}", name="PUT target")))


@pytest.mark.parametrize("case", sorted(BAD_DOCUMENTS))
def test_bad_documents_are_refused_with_a_problem_never_500(
    server: Server, put_target: str, case: str
) -> None:
    body, content_type = BAD_DOCUMENTS[case]
    before = twin_count(server)
    for method, path in (
        ("POST", "/api/v1/apply"),
        ("POST", "/api/v1/twins"),
        ("PUT", f"/api/v1/twins/{put_target}"),
    ):
        # A new connection each time: a 500 closes the connection it was sent on.
        with server.admin as admin:
            r = admin.request(method, path, content=body, headers={"Content-Type": content_type})
        assert r.status_code < 500, f"{method} {path}: {r.status_code} {r.text[:300]}"
        acceptable = MAY_BE_ACCEPTED | (PUT_MAY_ACCEPT if method == "PUT" else set())
        if case in acceptable and r.status_code < 300:
            continue
        assert 400 <= r.status_code < 500, f"{method} {path}: {r.status_code} {r.text[:300]}"
        assert r.headers["content-type"].startswith(PROBLEM)
        assert r.json()["detail"]
    if case not in MAY_BE_ACCEPTED:
        assert twin_count(server) == before


def test_bad_query_parameters_are_refused_with_a_problem(server: Server) -> None:
    with server.admin as admin:
        cases: list[tuple[str, dict[str, Any]]] = [
            ("/api/v1/twins", {"limit": 0}),
            ("/api/v1/twins", {"limit": "many"}),
            ("/api/v1/twins", {"cursor": "\x00weird"}),
            ("/api/v1/search", {"limit": 1000}),
            ("/api/v1/search", {"q": "x" * 300}),
            ("/api/v1/search", {"offset": -1}),
            (f"/api/v1/twins/{CRANE_SLUG}/relations", {"depth": 0}),
            (f"/api/v1/twins/{CRANE_SLUG}/relations", {"direction": "sideways"}),
            ("/api/v1/tokens", {"all": "perhaps"}),
        ]
        for path, params in cases:
            r = admin.get(path, params=params)
            assert r.status_code in (200, 422), f"{path} {params}: {r.status_code} {r.text[:300]}"
            if r.status_code == 422:
                assert r.headers["content-type"].startswith(PROBLEM)
        for body in (
            {"username": "has space", "password": "long-enough"},
            {"username": "ok", "password": "short"},
            {"username": "ok2", "password": "long-enough", "groups": ["bad group!"]},
            {"username": "ok3", "password": "long-enough", "is_admin": "maybe"},
        ):
            assert_problem(admin.post("/api/v1/users", json=body), 422)
        assert_problem(admin.post("/api/v1/users", content=b"{not json", headers=JSON_HEADERS), 422)


@pytest.fixture(autouse=True)
def _no_server_errors(server: Server) -> Iterator[None]:
    before = unhandled_errors(server)
    yield
    assert unhandled_errors(server) == before, f"the server logged: {last_error(server)}"


def test_examples_are_valid_documents() -> None:
    # Guards the fixtures the tests read: every example parses as a mapping with an id.
    for path in sorted(Path(ILMATAR).glob("*.yaml")):
        doc = load_yaml(path)
        assert doc["id"].startswith("http")
