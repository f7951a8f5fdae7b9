from __future__ import annotations

from twinlink.domain.merge import level_order, merge_parts, most_private

PUBLIC = {
    "version": "1.0",
    "privacy": "public",
    "id": "x",
    "name": "Crane",
    "contact": {"name": "Public desk", "email": "p@example.org"},
    "features": [
        {"name": "OPC UA", "description": "control", "requirement": "ask"},
        {"name": "Historian", "keywords": ["historical"]},
    ],
    "interface": {"signals": [{"name": "a", "unit": "m"}]},
    "relations": [{"relationType": "parent", "id": "hall"}],
}
GROUP = {
    "version": "0.1",
    "privacy": "group-1",
    "id": "x",
    "contact": {"name": "Lab desk"},
    "features": [{"name": "OPC UA", "address": "10.0.0.7"}, {"name": "Booking"}],
    "interface": {"signals": [{"name": "a", "max": 3}, {"name": "b"}]},
}
PRIVATE = {
    "version": "0.0.1",
    "privacy": "private",
    "id": "x",
    "features": [{"name": "OPC UA", "requirement": "password: secret"}],
}


def test_levels_order_public_groups_private() -> None:
    assert sorted(["private", "group-2", "public", "group-1"], key=level_order) == [
        "public",
        "group-1",
        "group-2",
        "private",
    ]
    assert most_private(["public", "group-1"]) == "group-1"
    assert most_private([]) == "public"


def test_merge_features_by_name_more_private_wins() -> None:
    doc = merge_parts({"private": PRIVATE, "public": PUBLIC, "group-1": GROUP})
    opc = next(f for f in doc["features"] if f["name"] == "OPC UA")
    assert opc == {
        "name": "OPC UA",
        "description": "control",
        "requirement": "password: secret",
        "address": "10.0.0.7",
    }
    assert [f["name"] for f in doc["features"]] == ["OPC UA", "Historian", "Booking"]
    assert doc["privacy"] == "private"


def test_mappings_merge_key_by_key() -> None:
    doc = merge_parts({"public": PUBLIC, "group-1": GROUP})
    assert doc["contact"] == {"name": "Lab desk", "email": "p@example.org"}


def test_interface_entries_merge_by_name() -> None:
    doc = merge_parts({"public": PUBLIC, "group-1": GROUP})
    assert doc["interface"]["signals"] == [{"name": "a", "unit": "m", "max": 3}, {"name": "b"}]


def test_public_only_reader_sees_public_only() -> None:
    doc = merge_parts({"public": PUBLIC})
    assert "password: secret" not in str(doc)
    assert doc["privacy"] == "public"


def test_relations_are_left_to_the_graph_and_inputs_untouched() -> None:
    before = str(PUBLIC)
    doc = merge_parts({"public": PUBLIC})
    assert "relations" not in doc
    assert str(PUBLIC) == before
