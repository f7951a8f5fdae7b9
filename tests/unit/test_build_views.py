from __future__ import annotations

from typing import Any

import orjson
import pytest

from twinlink.domain.document import validate_part
from twinlink.domain.records import Edge, TwinRecord
from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.build import (
    declared_edges,
    human_time,
    imported_created_ns,
    machine_time,
    search_rows,
)
from twinlink.registry.readback import is_view_of
from twinlink.registry.views import declared_entries, relation_entries, render_document


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


def test_imported_times_are_exact_and_may_be_before_1970() -> None:
    assert imported_created_ns({"createdMachine": "1605277810.555"}) == 1_605_277_810_555_000_000
    assert imported_created_ns({"createdMachine": -86400}) == -86_400 * 10**9
    assert imported_created_ns({"createdHuman": "1969-12-31"}) == -86_400 * 10**9
    # Out of range was refused by validation; here it reads as no time rather than overflow.
    assert imported_created_ns({"createdMachine": 9_300_000_000}) is None


def test_relation_entries_keep_the_keys_the_twin_wrote() -> None:
    edges = [Edge("P", "parent", "X", "X", "public"), Edge("X", "parent", "C", "C", "public")]
    written = {"relationType": "parent", "dt-id": "P", "note": "bolted"}
    parts = {"public": {"relations": [written]}}
    assert relation_entries("X", edges, "id", declared_entries(parts)) == [
        written,  # as written, `dt-id` and all
        {"relationType": "child", "id": "C"},  # declared by C: only what the graph knows
    ]


def _twin() -> TwinRecord:
    return TwinRecord(1, "crane", "urn:crane", "Crane", 10**18, 10**18, "public", [])


PARTS: dict[str, dict[str, Any]] = {
    "public": {
        "version": "1.0",
        "privacy": "public",
        "id": "urn:crane",
        "name": "Crane",
        "features": [{"name": "OPC UA", "requirement": "ask"}],
        "relations": [{"relationType": "parent", "id": "urn:hall", "note": "rails"}],
    },
    "group-1": {
        "version": "0.1",
        "privacy": "group-1",
        "id": "urn:crane",
        "features": [{"name": "OPC UA", "address": "10.0.0.7"}],
    },
    "private": {"version": "1.0", "privacy": "private", "id": "urn:crane", "secret": "s"},
}
EDGES = [Edge("urn:hall", "parent", "urn:crane", "urn:crane", "public")]
URL = "http://host/twins/crane"


@pytest.mark.parametrize(
    ("levels", "level"),
    [
        (["public", "group-1"], "group-1"),
        (list(PARTS), "private"),
        (["public"], "public"),
        (["private"], "private"),
    ],
)
def test_a_view_read_back_is_recognised_for_any_reader(levels: list[str], level: str) -> None:
    view = render_document(_twin(), {lv: PARTS[lv] for lv in levels}, EDGES, URL)
    body = orjson.loads(orjson.dumps(view))
    assert is_view_of(body, level, PARTS, _twin(), URL, EDGES)
    changed = {**body, "name": "Renamed"}
    assert not is_view_of(changed, level, PARTS, _twin(), URL, EDGES)
    # Relations: one the graph lacks, or the twin's own entry without its note, is a change.
    extra = {**body, "relations": [*body["relations"], {"relationType": "child", "id": "urn:x"}]}
    assert not is_view_of(extra, level, PARTS, _twin(), URL, EDGES)
    bare = {**body, "relations": [{"relationType": "parent", "id": "urn:hall"}]}
    assert is_view_of(bare, level, PARTS, _twin(), URL, EDGES) is ("public" not in levels)
