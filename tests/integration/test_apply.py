"""Applying DT documents over HTTP: idempotency, create and update, JSON bodies, timestamps."""

from __future__ import annotations

import json

import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    JSON_HEADERS,
    YAML_HEADERS,
    _feature,
    apply,
    assert_problem,
    get_doc,
    slug_of,
    twin_doc,
    unique,
    wait_for_clock_past,
)

pytestmark = pytest.mark.integration

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


# -- JSON bodies, create and update ---------------------------------------------------------


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
