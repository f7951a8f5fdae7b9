from __future__ import annotations

from twinlink.domain.document import validate_part
from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.build import (
    declared_edges,
    human_time,
    imported_created_ns,
    machine_time,
    search_rows,
)
from twinlink.registry.views import relation_entries, render_document
from twinlink.store.records import Edge, TwinRecord


def part(data: dict) -> object:  # type: ignore[type-arg]
    return validate_part(SourceDocument({"version": "1.0", **data}))[0]


def test_declared_edges_normalise_each_relation_type() -> None:
    models = {
        "public": part(
            {
                "relations": [
                    {"relationType": "parent", "id": "P"},
                    {"relationType": "child", "dt-id": "C"},
                    {"relationType": "sibling", "id": "A"},
                ]
            }
        )
    }
    edges = {(e.source, e.kind, e.target) for e in declared_edges("X", models)}  # type: ignore[arg-type]
    assert edges == {("P", "parent", "X"), ("X", "parent", "C"), ("A", "sibling", "X")}


def test_relation_entries_seen_from_either_end() -> None:
    edges = [
        Edge("P", "parent", "X", "P", "public"),
        Edge("X", "parent", "C", "X", "public"),
        Edge("A", "sibling", "X", "X", "public"),
        Edge("P", "parent", "X", "X", "public"),
    ]
    assert relation_entries("X", edges, "id") == [
        {"relationType": "parent", "id": "P"},
        {"relationType": "child", "id": "C"},
        {"relationType": "sibling", "id": "A"},
    ]


def test_search_rows_cover_twin_and_features_per_part() -> None:
    rows = search_rows(
        {
            "public": {
                "id": "http://d-t.fi/ilmatar-K16052",
                "name": "Crane",
                "owner": {"name": "Uni"},
                "custom": "blue",
                "features": [{"name": "CAD store", "keywords": "CAD", "requirement": "account"}],
            },
            "private": {"features": [{"name": "Secret"}]},
        }
    )
    twin = rows[0]
    assert (twin.feature, twin.name, twin.privacy) == (None, "Crane", "public")
    assert "Uni" in twin.extra and "blue" in twin.extra and "ilmatar-K16052" in twin.extra
    cad = rows[1]
    assert (cad.feature, cad.keywords, cad.extra) == ("CAD store", ["CAD"], "account")
    assert [(r.privacy, r.feature) for r in rows[2:]] == [("private", None), ("private", "Secret")]


def test_times() -> None:
    ns = 1_605_277_810_555_000_000
    assert machine_time(ns) == "1605277810"
    assert human_time(ns) == "2020-11-13T14:30:10.555Z"
    assert imported_created_ns({"createdMachine": "1605277810"}) == 1_605_277_810 * 10**9
    assert imported_created_ns({"createdHuman": "2020-11-13T14:30:10.555Z"}) == ns
    assert imported_created_ns({"createdMachine": "soon"}) is None
    assert imported_created_ns({}) is None


def test_render_document_order_times_and_hosting_iri() -> None:
    twin = TwinRecord(
        1, "crane", "http://d/crane", "Crane", 10**18, 2 * 10**18, "public", ["public"]
    )
    parts = {
        "public": {
            "version": "1.0",
            "privacy": "public",
            "dt-id": "http://d/crane",
            "name": "Crane",
            "zzz": 1,
            "features": [{"name": "f"}],
        }
    }
    doc = render_document(
        twin,
        parts,
        [Edge("http://d/hall", "parent", "http://d/crane", "x", "public")],
        "http://host/twins/crane",
    )
    keys = list(doc)
    assert keys[:5] == ["version", "privacy", "dt-id", "hosting-iri", "name"]
    assert keys.index("modifiedHuman") < keys.index("zzz")
    assert keys.index("relations") < keys.index("features")
    assert doc["relations"] == [{"relationType": "parent", "dt-id": "http://d/hall"}]
    assert doc["hosting-iri"] == "http://host/twins/crane"
    assert doc["createdMachine"] == "1000000000"
