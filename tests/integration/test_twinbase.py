"""Published Twinbase documents (tests/unit/fixtures/twinbase/, unchanged) import over HTTP as
they are, read back with every key, and apply again as `unchanged`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import httpx
import pytest
import yaml

from tests.conftest import ROOT, Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import JSON_HEADERS, YAML_HEADERS, get_doc

pytestmark = pytest.mark.integration

TWINBASE = ROOT / "tests" / "unit" / "fixtures" / "twinbase"
DOCUMENTS = sorted(p for p in TWINBASE.iterdir() if p.suffix in (".yaml", ".json"))


def _post(client: httpx.Client, path: Path) -> dict[str, Any]:
    headers = JSON_HEADERS if path.suffix == ".json" else YAML_HEADERS
    r = client.post("/api/v1/apply", content=path.read_bytes(), headers=headers)
    assert r.status_code == 200, f"{path.name}: {r.text}"
    [result] = r.json()["results"]
    return result  # type: ignore[no-any-return]


def _as_published(path: Path) -> dict[str, Any]:
    data = yaml.safe_load(path.read_text("utf-8"))  # JSON is YAML
    assert isinstance(data, dict)
    return data


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: p.name)
def test_a_published_twinbase_document_imports_and_reads_back(server: Server, path: Path) -> None:
    published = _as_published(path)
    with server.admin as admin:
        first = _post(admin, path)
        assert first["outcome"] in ("created", "unchanged")  # .yaml and .json of one twin
        slug = first["slug"]
        doc = get_doc(admin, slug)
        again = _post(admin, path)
    assert again["outcome"] == "unchanged"
    assert again["modified"] == first["modified"]
    assert "version" not in doc or doc["version"] == published.get("version")
    for key, value in published.items():
        if key == "relations":
            # Shown from the graph; the twin's own entries exactly as written.
            for entry in value:
                assert entry in doc["relations"], entry
        elif value == "autoassign":
            continue  # filled in: see the test below
        elif key == "dt-id" and str(value).startswith("autoassign|"):
            assert doc["dt-id"] == f"{value.split('|', 1)[1]}/{slug}"
        else:
            assert doc[key] == value, key


def test_twinbase_placeholders_are_filled_in_as_twinbase_would(server: Server) -> None:
    """`dt-id: autoassign|BASE` names the twin BASE/{slug}, as Twinbase names it
    BASE/{folder}; `hosting-iri: autoassign` is the twin's address here."""
    path = TWINBASE / "test-twin-1-autoassign.yaml"
    with server.admin as admin:
        result = _post(admin, path)
        slug = result["slug"]
        assert slug == "test-twin-1"
        doc = get_doc(admin, slug)
        stored = admin.get(f"/api/v1/twins/{slug}/parts/private").json()
        view = admin.get(f"/twins/{slug}/index.yaml")
        back = admin.post("/api/v1/apply", content=view.content, headers=YAML_HEADERS)
    assert result["id"] == "https://dtid.org/test-twin-1" == doc["dt-id"] == stored["dt-id"]
    assert doc["hosting-iri"] == f"{server.url}/twins/{slug}"
    assert "hosting-iri" not in stored
    # A document without `privacy` is private, Twinbase's as any other.
    assert doc["privacy"] == "private"
    assert back.status_code == 200, back.text
    assert back.json()["results"][0]["outcome"] == "unchanged"


def test_twinbase_relations_by_dt_id_join_the_graph(server: Server) -> None:
    with server.admin as admin:
        crane = _post(admin, TWINBASE / "crane-ilmatar.yaml")["slug"]
        hall = _post(admin, TWINBASE / "lab-room-K3-143.yaml")["slug"]
        tree = admin.get(f"/api/v1/twins/{hall}/relations").json()
        crane_doc = get_doc(admin, crane)
    assert [n["slug"] for n in tree["nodes"]] == [crane]
    # Both documents write the relation; it is one edge, shown once, with `dt-id`.
    assert crane_doc["relations"] == [
        {"dt-id": "http://d-t.fi/3091b292-6104-4ef3-a30f-8275b46b5ab4", "relationType": "parent"}
    ]
