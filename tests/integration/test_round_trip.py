"""A document read from twinlink and applied again changes nothing: every example twin, as
every kind of reader gets it, as YAML and as JSON. Relation entries keep their own keys, the
filled-in `hosting-iri` is not stored, and a changed merged view is refused, not stored as
the most private part."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import httpx
import pytest
import yaml

from tests.conftest import Server, start_server, stop_server
from tests.integration._util import (
    CRANE_SLUG,
    ILMATAR,
    JSON_HEADERS,
    YAML_HEADERS,
    apply,
    assert_problem,
    example_documents,
    get_doc,
    last_error,
    load_yaml,
    make_user,
    slug_of,
    twin_doc,
    unhandled_errors,
    unique,
)

pytestmark = pytest.mark.integration

TIMES = ("createdMachine", "createdHuman", "modifiedMachine", "modifiedHuman")


@dataclass
class Platform:
    server: Server
    slugs: list[str]  # the example twins
    readers: dict[str, str | None]  # who -> token (None: anonymous)


@pytest.fixture(scope="module")
def platform(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Platform]:
    """Its own server: the tests below compare whole documents, which other modules' twins
    (relations to the examples) would change under them."""
    server = start_server(tmp_path_factory.mktemp("roundtrip"))
    try:
        slugs = []
        with server.admin as admin:
            for path in example_documents():
                r = admin.post("/api/v1/apply", content=path.read_bytes(), headers=YAML_HEADERS)
                assert r.status_code == 200, f"{path.name}: {r.text}"
                slugs.extend(x["slug"] for x in r.json()["results"])
        viewer = unique("viewer")
        readers: dict[str, str | None] = {
            "anonymous": None,
            "group-1 member": make_user(server, unique("member"), groups=["group-1"]),
            "viewer": make_user(server, viewer),
            "admin": server.admin_token,
        }
        with server.admin as admin:
            r = admin.put(f"/api/v1/twins/{CRANE_SLUG}/roles/{viewer}", json={"role": "viewer"})
            assert r.status_code == 200, r.text
        yield Platform(server, sorted(set(slugs)), readers)
        assert unhandled_errors(server) == 0, last_error(server)
    finally:
        stop_server(server)


def _read(client: httpx.Client, slug: str, form: str) -> tuple[bytes, dict[str, str]]:
    """The document as a reader gets it, ready to send back."""
    if form == "yaml":
        r = client.get(f"/twins/{slug}/index.yaml")
    elif form == "json":
        r = client.get(f"/twins/{slug}/index.json")
    else:  # the API's answer, whose `document` a client would send back
        r = client.get(f"/api/v1/twins/{slug}")
    assert r.status_code == 200, r.text
    if form == "api":
        return json.dumps(r.json()["document"]).encode(), JSON_HEADERS
    return r.content, YAML_HEADERS if form == "yaml" else JSON_HEADERS


def _everything(admin: httpx.Client, slug: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """The whole twin as its owner sees it, and every stored part."""
    doc = get_doc(admin, slug)
    levels = admin.get(f"/api/v1/twins/{slug}/parts").json()["levels"]
    parts = {lv: admin.get(f"/api/v1/twins/{slug}/parts/{lv}").json() for lv in levels}
    return doc, parts


# Anonymous readers get the canonical URLs; the API wants a token.
READS = [
    (reader, form)
    for reader in ("anonymous", "group-1 member", "viewer", "admin")
    for form in ("yaml", "json", "api")
    if (reader, form) != ("anonymous", "api")
]


@pytest.mark.parametrize(("reader", "form"), READS)
def test_every_example_read_and_applied_again_is_unchanged(
    platform: Platform, reader: str, form: str
) -> None:
    server = platform.server
    assert len(platform.slugs) >= 3
    with server.client(platform.readers[reader]) as client, server.admin as admin:
        for slug in platform.slugs:
            body, headers = _read(client, slug, form)
            before = _everything(admin, slug)
            # Through both doors: apply (by the document's id) and PUT (by the slug).
            for method, path in (("POST", "/api/v1/apply"), ("PUT", f"/api/v1/twins/{slug}")):
                r = admin.request(method, path, content=body, headers=headers)
                assert r.status_code == 200, f"{slug} as {reader} ({form}): {r.text}"
                answer = r.json()["results"][0] if method == "POST" else r.json()
                assert answer["outcome"] == "unchanged", f"{slug} as {reader} ({form}), {method}"
            assert _everything(admin, slug) == before, slug


def test_the_crane_views_differ_by_reader(platform: Platform) -> None:
    """The test above is about different documents: each reader's view of the crane is its
    own (so a view applied back is recognised whichever parts it was merged from)."""
    server = platform.server
    views = {}
    for reader, token in platform.readers.items():
        with server.client(token) as client:
            views[reader] = yaml.safe_load(_read(client, CRANE_SLUG, "yaml")[0])
    assert [views[r]["privacy"] for r in platform.readers] == [
        "public",
        "group-1",
        "group-1",
        "private",
    ]
    assert views["anonymous"] != views["group-1 member"] != views["admin"]


# -- relation entries ----------------------------------------------------------------------


def test_relation_entries_keep_their_own_keys(platform: Platform) -> None:
    server = platform.server
    hall, crane = f"urn:test:{unique('hall')}", f"urn:test:{unique('crane')}"
    entry = {
        "relationType": "parent",
        "id": hall,
        "note": "hangs from the hall's rails",
        "since": {"year": 2017, "verified": True},
    }
    crane_doc = twin_doc(crane, name="Crane with notes") + yaml.safe_dump(
        {"relations": [entry]}, sort_keys=False
    )
    with server.admin as admin:
        hall_slug = slug_of(apply(admin, twin_doc(hall, name="Hall")))
        crane_slug = slug_of(apply(admin, crane_doc))
        shown = get_doc(admin, crane_slug)["relations"]
        other_end = get_doc(admin, hall_slug)["relations"]
        stored = admin.get(f"/api/v1/twins/{crane_slug}/parts/public").json()["relations"]
        assert shown == [entry] and stored == [entry]
        # The other end shows the relation the graph has, without the crane's own notes.
        assert other_end == [{"relationType": "child", "id": crane}]
        for slug in (crane_slug, hall_slug):
            for form in ("yaml", "json"):
                body, headers = _read(admin, slug, form)
                r = admin.post("/api/v1/apply", content=body, headers=headers)
                assert r.status_code == 200, r.text
                assert r.json()["results"][0]["outcome"] == "unchanged", (slug, form)
        # A changed note is a change.
        changed = crane_doc.replace("hangs from the hall's rails", "bolted to the rails")
        [result] = apply(admin, changed).json()["results"]
        assert result["outcome"] == "updated"
        assert get_doc(admin, crane_slug)["relations"][0]["note"] == "bolted to the rails"


def test_relation_notes_in_a_private_part_stay_private(platform: Platform) -> None:
    server = platform.server
    a, b = f"urn:test:{unique('a')}", f"urn:test:{unique('b')}"
    public = twin_doc(a, name="Noted") + yaml.safe_dump(
        {"relations": [{"relationType": "sibling", "id": b}]}
    )
    private = twin_doc(a, privacy="private") + yaml.safe_dump(
        {"relations": [{"relationType": "sibling", "id": b, "note": "secret reason"}]}
    )
    with server.admin as admin:
        slug = slug_of(apply(admin, public, private))
        assert get_doc(admin, slug)["relations"][0]["note"] == "secret reason"
    with server.client() as anon:
        r = anon.get(f"/twins/{slug}/index.json")
    assert r.json()["relations"] == [{"relationType": "sibling", "id": b}]
    assert "secret reason" not in r.text


# -- what the platform fills in ------------------------------------------------------------


def test_an_edited_view_stores_neither_timestamps_nor_the_filled_in_hosting_iri(
    platform: Platform,
) -> None:
    server = platform.server
    with server.admin as admin:
        slug = slug_of(apply(admin, twin_doc(f"urn:test:{unique('iri')}", name="Plain")))
        view = yaml.safe_load(admin.get(f"/twins/{slug}/index.yaml").text)
        assert view["hosting-iri"] == f"{server.url}/twins/{slug}"
        view["description"] = "edited in the view"
        r = admin.post("/api/v1/apply", content=yaml.safe_dump(view), headers=YAML_HEADERS)
        assert r.status_code == 200, r.text
        assert r.json()["results"][0]["outcome"] == "updated"
        stored = admin.get(f"/api/v1/twins/{slug}/parts/public").json()
        assert stored["description"] == "edited in the view"
        assert "hosting-iri" not in stored
        assert not set(TIMES) & set(stored)
        # A hosting-iri of its own is kept.
        view["hosting-iri"] = "https://elsewhere.example/plain"
        r = admin.post("/api/v1/apply", content=yaml.safe_dump(view), headers=YAML_HEADERS)
        assert r.json()["results"][0]["outcome"] == "updated"
        stored = admin.get(f"/api/v1/twins/{slug}/parts/public").json()
        assert stored["hosting-iri"] == "https://elsewhere.example/plain"


# -- merged views --------------------------------------------------------------------------


def _split_crane(admin: httpx.Client) -> str:
    """The example crane's three parts under an id of its own, so they can be changed."""
    dt_id = f"urn:test:{unique('split')}"
    docs = []
    for name in ("ilmatar-public.yaml", "ilmatar-group.yaml", "ilmatar-private.yaml"):
        doc = load_yaml(ILMATAR / name)
        doc["id"] = dt_id
        doc.pop("relations", None)
        docs.append(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True))
    return slug_of(apply(admin, *docs))


@pytest.mark.parametrize("reader", ["group-1 member", "admin"])
def test_a_changed_merged_view_is_refused_not_copied_into_one_part(
    platform: Platform, reader: str
) -> None:
    server = platform.server
    with server.admin as admin:
        slug = _split_crane(admin)
        before = _everything(admin, slug)
    with server.client(platform.readers[reader]) as client:
        view = yaml.safe_load(client.get(f"/twins/{slug}/index.yaml").text)
    assert view["privacy"] == ("group-1" if reader != "admin" else "private")
    view["description"] = "changed in the merged view"
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=yaml.safe_dump(view), headers=YAML_HEADERS)
        body = assert_problem(r, 422)
        [problem] = body["errors"]
        assert problem["path"] == "privacy"
        assert "merged" in body["detail"]
        assert f"/api/v1/twins/{slug}/parts/" in problem["message"]
        assert "createdMachine" in problem["message"]  # how to store it as one part anyway
        assert _everything(admin, slug) == before

        # Without the platform's timestamps it is taken as the part it says it is.
        for key in TIMES:
            del view[key]
        r = admin.post("/api/v1/apply", content=yaml.safe_dump(view), headers=YAML_HEADERS)
        assert r.status_code == 200, r.text
        assert r.json()["results"][0]["outcome"] == "updated"
        stored = admin.get(f"/api/v1/twins/{slug}/parts/{view['privacy']}").json()
    assert stored["description"] == "changed in the merged view"


def test_a_changed_public_view_updates_the_public_part_only(platform: Platform) -> None:
    server = platform.server
    with server.admin as admin:
        slug = _split_crane(admin)
        _, parts_before = _everything(admin, slug)
    with server.client() as anon:
        view = anon.get(f"/twins/{slug}/index.json").json()
    view["description"] = "changed in the public view"
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}", content=json.dumps(view), headers=JSON_HEADERS)
        assert r.status_code == 200, r.text
        assert r.json()["outcome"] == "updated"
        _, parts = _everything(admin, slug)
    assert parts["public"]["description"] == "changed in the public view"
    assert parts["public"]["features"] == parts_before["public"]["features"]
    assert {k: v for k, v in parts.items() if k != "public"} == {
        k: v for k, v in parts_before.items() if k != "public"
    }
