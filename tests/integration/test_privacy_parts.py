"""Privacy parts over HTTP: what each reader sees of a split twin, how parts merge, unknown
keys, and the canonical URL (content negotiation, HTML)."""

from __future__ import annotations

import html
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
import yaml

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    CRANE_SLUG,
    ILMATAR,
    YAML_HEADERS,
    _feature,
    apply,
    assert_problem,
    get_doc,
    load_yaml,
    make_user,
    slug_of,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

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


def test_examples_are_valid_documents() -> None:
    # Guards the fixtures the tests read: every example parses as a mapping with an id.
    for path in sorted(Path(ILMATAR).glob("*.yaml")):
        doc = load_yaml(path)
        assert doc["id"].startswith("http")
