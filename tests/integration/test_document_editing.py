"""What the web app's document editor relies on: a part read back as YAML applies unchanged,
and a dry run checks an edit (its problems at their lines, the editor role) without storing it."""

from __future__ import annotations

import pytest
import yaml

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    YAML_HEADERS,
    apply,
    assert_problem,
    get_doc,
    make_user,
    slug_of,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration


def _twin(server: Server) -> str:
    doc = twin_doc(
        f"urn:test:{unique('edit')}",
        name="Pump 7",
        description="a pump: with a colon",
        features=[{"name": "Flow", "keywords": ["flow", "l/min"], "address": "http://x/flow"}],
    )
    with server.admin as admin:
        return slug_of(apply(admin, doc))


def test_a_part_read_as_yaml_applies_unchanged(server: Server) -> None:
    slug = _twin(server)
    with server.admin as admin:
        as_json = admin.get(f"/api/v1/twins/{slug}/parts/public").json()
        r = admin.get(f"/api/v1/twins/{slug}/parts/public", params={"format": "yaml"})
        assert r.status_code == 200 and r.headers["content-type"].startswith("application/yaml")
        assert yaml.safe_load(r.text) == as_json
        put = admin.put(f"/api/v1/twins/{slug}", content=r.content, headers=YAML_HEADERS)
        assert put.status_code == 200, put.text
        assert put.json()["outcome"] == "unchanged"
        bad = admin.get(f"/api/v1/twins/{slug}/parts/public", params={"format": "xml"})
        assert_problem(bad, 422)


def test_a_dry_run_checks_an_edit_and_stores_nothing(server: Server) -> None:
    slug = _twin(server)
    with server.admin as admin:
        text = admin.get(f"/api/v1/twins/{slug}/parts/public", params={"format": "yaml"}).text
        edited = text.replace("name: Pump 7", "name: Pump 8")
        url = f"/api/v1/twins/{slug}"
        r = admin.put(
            url, params={"dry_run": "true"}, content=edited.encode(), headers=YAML_HEADERS
        )
        assert r.status_code == 200, r.text
        assert (r.json()["outcome"], r.json()["dry_run"]) == ("updated", True)
        assert get_doc(admin, slug)["name"] == "Pump 7"
        # A schema problem and malformed YAML are both named at their line.
        lines = edited.splitlines()
        at = next(i for i, line in enumerate(lines) if line.startswith("features:"))
        broken = [*lines[: at + 1], "- description: no name here", *lines[at + 1 :]]
        r = admin.put(
            url,
            params={"dry_run": "true"},
            content="\n".join(broken).encode(),
            headers=YAML_HEADERS,
        )
        problem = assert_problem(r, 422)
        assert problem["errors"][0]["line"] == at + 2, problem
        r = admin.put(
            url,
            params={"dry_run": "true"},
            content=b"name: [unclosed\nprivacy: public\n",
            headers=YAML_HEADERS,
        )
        assert assert_problem(r, 422)["errors"][0]["line"] in (2, 3)
        assert get_doc(admin, slug)["name"] == "Pump 7"


def test_a_dry_run_needs_the_editor_role(server: Server) -> None:
    slug = _twin(server)
    name = unique("viewer")
    token = make_user(server, name)
    with server.admin as admin:
        grant = admin.put(f"/api/v1/twins/{slug}/roles/{name}", json={"role": "viewer"})
        assert grant.status_code == 200, grant.text
        text = admin.get(f"/api/v1/twins/{slug}/parts/public", params={"format": "yaml"}).text
    with server.client(token) as viewer:
        r = viewer.put(
            f"/api/v1/twins/{slug}",
            params={"dry_run": "true"},
            content=text.encode(),
            headers=YAML_HEADERS,
        )
    assert_problem(r, 403)
