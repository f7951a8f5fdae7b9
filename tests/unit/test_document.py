from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.domain.document import validate_part
from twinlink.domain.errors import DocumentError
from twinlink.domain.yamlsource import parse_yaml_stream

FIXTURES = Path(__file__).parent / "fixtures"


def load(text: str):  # type: ignore[no-untyped-def]
    return validate_part(parse_yaml_stream(text)[0])


def problems(text: str) -> list[tuple[int | None, str, str]]:
    with pytest.raises(DocumentError) as caught:
        load(text)
    return [(p.line, p.path, p.message) for p in caught.value.problems]


@pytest.mark.parametrize("name", ["public", "group", "private"])
def test_published_privacy_split_parts_are_accepted(name: str) -> None:
    part, raw = load((FIXTURES / f"published-style-{name}.yaml").read_text())
    assert part.global_id == "http://d-t.fi/example-crane-1"
    assert raw["privacy"] == part.privacy


def test_parts_without_name_are_accepted_as_published() -> None:
    part, _ = load((FIXTURES / "published-style-private.yaml").read_text())
    assert part.name is None
    assert part.version == "0.0.1"


def test_twinbase_dt_id_hosting_iri_and_mapping_owner() -> None:
    part, raw = load((FIXTURES / "twinbase-style.yaml").read_text())
    assert part.global_id == "http://d-t.fi/example-crane-2"
    assert part.hosting_iri == "https://twins.example.org/crane-two"
    assert part.relations[0].target == "http://d-t.fi/example-hall"
    assert raw["edit"].startswith("https://")  # unknown key kept
    assert raw["owner"] == {"name": "A university foundation", "website": "https://example.org"}


def test_platform_timestamps_are_not_stored_from_input() -> None:
    _, raw = load((FIXTURES / "published-style-public.yaml").read_text())
    assert "createdMachine" not in raw and "modifiedHuman" not in raw


def test_unquoted_version_number_becomes_text() -> None:
    part, raw = load("version: 1.0\nprivacy: public\nname: x\n")
    assert part.version == "1.0" and raw["version"] == "1.0"


def test_privacy_defaults_to_private() -> None:
    part, _ = load('version: "1.0"\nname: x\n')
    assert part.privacy == "private"


def test_custom_keys_and_single_keyword() -> None:
    part, raw = load(
        'version: "1.0"\nname: x\nmy-key: {a: 1}\nfeatures:\n'
        "  - name: f\n    keywords: cad\n    dataRetention: 5 years\n"
    )
    assert part.features[0].keywords == ["cad"]
    assert raw["my-key"] == {"a": 1}
    assert raw["features"][0]["dataRetention"] == "5 years"


def test_every_problem_is_reported_with_its_line() -> None:
    text = (
        'version: "2.5"\n'  # 1
        "privacy: public\n"  # 2
        "name: [1, 2]\n"  # 3
        "relations:\n"  # 4
        "  - relationType: uncle\n"  # 5
        "    id: y\n"  # 6
        "  - relationType: parent\n"  # 7
        "features:\n"  # 8
        "  - description: no name\n"  # 9
        "  - name: A\n"  # 10
        "  - name: A\n"  # 11
        "interface:\n"  # 12
        "  signals:\n"  # 13
        "    - name: s\n"  # 14
        "      type: float\n"  # 15
        "    - name: t\n"  # 16
        "      min: 5\n"  # 17
        "      max: 1\n"  # 18
    )
    found = problems(text)
    lines = {line for line, _, _ in found}
    assert {3, 5, 7, 9, 15, 16}.issubset(lines)
    assert any("relationType" in path for _, path, _ in found)
    assert any("must be 'parent', 'child' or 'sibling'" in m for _, _, m in found)
    assert any(path == "features[0].name" and "missing" in m for _, path, m in found)
    assert any("min (5.0) is greater than max (1.0)" in m for _, _, m in found)


def test_version_and_duplicates_are_rules_checked_after_types() -> None:
    found = problems('version: "2.5"\nname: x\nfeatures:\n  - name: A\n  - name: A\n')
    assert (1, "version", found[0][2]) in found and "unsupported version" in found[0][2]
    assert any(line == 5 and "duplicate feature name" in m for line, _, m in found)


def test_id_and_dt_id_must_agree() -> None:
    found = problems('version: "1.0"\nname: x\nid: a\ndt-id: b\n')
    assert found[0][1] == "dt-id"


def test_top_level_must_be_a_mapping() -> None:
    assert "found list" in problems("- a\n- b\n")[0][2]
    assert "found empty" in problems("---\n")[0][2]


def test_interface_types() -> None:
    part, _ = load(
        'version: "1.0"\nname: x\ninterface:\n  signals:\n'
        "    - {name: a, unit: rad, min: 0, max: 1}\n"
        "  properties:\n    - {name: rate, type: number, writable: true}\n"
        "  commands:\n    - name: set\n      parameters:\n        - {name: v, required: true}\n"
    )
    assert part.interface is not None
    assert part.interface.signals[0].unit == "rad"
    assert part.interface.properties[0].writable is True
    assert part.interface.commands[0].parameters[0].required is True


def test_only_plain_data_is_accepted() -> None:
    found = problems('version: "1.0"\nname: x\n1: int key\nb: !!binary aGVsbG8=\nc: .nan\n')
    messages = {(line, m) for line, _, m in found}
    assert (3, "key 1 must be text (quote it)") in messages
    assert (4, "values of type bytes are not allowed here") in messages
    assert (5, "not-a-number and infinite values are not allowed") in messages
