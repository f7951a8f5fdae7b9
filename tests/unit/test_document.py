from __future__ import annotations

from pathlib import Path
from typing import Any

import orjson
import pytest

from twinlink.domain.document import validate_part
from twinlink.domain.errors import DocumentError
from twinlink.domain.jsontext import fits_int64, int64_problem, loads_document
from twinlink.domain.yamlsource import SourceDocument, format_path, parse_yaml_stream
from twinlink.registry.build import imported_created_ns

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


# -- Twinbase documents --------------------------------------------------------------------

TWINBASE = FIXTURES / "twinbase"


def _fixture(path: Path) -> SourceDocument:
    if path.suffix == ".json":
        return SourceDocument(loads_document(path.read_bytes()))
    [doc] = parse_yaml_stream(path.read_text("utf-8"))
    return doc


@pytest.mark.parametrize(
    "path", sorted(p for p in TWINBASE.iterdir() if p.suffix in (".yaml", ".json")), ids=str
)
def test_published_twinbase_documents_are_valid_as_they_are(path: Path) -> None:
    source = _fixture(path)
    part, raw = validate_part(source)
    assert part.dt_id == source.data["dt-id"]
    if "version" not in source.data:
        assert part.version is None and "version" not in raw  # none is made up
    for key, value in source.data.items():  # every key kept (a placeholder is filled in later)
        if key != "hosting-iri" or value != "autoassign":
            assert raw[key] == value, key


def test_a_document_without_version_or_dt_id_is_refused_naming_both_formats() -> None:
    [(line, path, message)] = problems("id: urn:x\nname: x\n")
    assert (line, path) == (1, "version")
    assert "required key `version` is missing" in message and "Twinbase" in message
    assert problems("version: null\nname: x\n")[0][2].startswith("version is empty")


def test_twinbase_placeholders_are_left_for_the_platform_to_fill_in() -> None:
    part, raw = load((TWINBASE / "test-twin-1-autoassign.yaml").read_text())
    assert part.global_id is None  # the twin is found by its slug, named after its name
    assert part.id_base == "https://dtid.org"
    assert part.hosting_iri is None and "hosting-iri" not in raw
    assert raw["dt-id"] == "autoassign|https://dtid.org"  # the applier puts the real id here
    plain, _ = load("dt-id: https://dtid.org/x\nname: x\n")
    assert (plain.global_id, plain.id_base) == ("https://dtid.org/x", None)


# -- numbers and times -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("createdMachine: 9300000000", "Unix seconds from -9223372036 to 9223372036"),
        ("createdMachine: '-9300000000.5'", "Unix seconds from -9223372036 to 9223372036"),
        ("modifiedMachine: '1e999999'", "Unix seconds from"),
        ("createdHuman: '9999-12-31T23:59:59Z'", "1677-09-21T00:12:44Z to 2262-04-11T23:47:16Z"),
        ("createdHuman: '1000-01-01'", "1677-09-21T00:12:44Z to 2262-04-11T23:47:16Z"),
        ("modifiedHuman: '2262-04-11T23:47:17Z'", "to 2262-04-11T23:47:16Z"),
    ],
)
def test_times_outside_what_int64_nanoseconds_hold_are_refused(line: str, message: str) -> None:
    [(at, path, text)] = problems(f"version: '1.0'\nname: x\n{line}\n")
    assert (at, path) == (3, line.split(":")[0])
    assert "outside the times twinlink can hold" in text and message in text


@pytest.mark.parametrize(
    "line",
    [
        "createdMachine: -9223372036",
        "createdMachine: 9223372036",
        "createdMachine: 0",
        "createdHuman: '1677-09-21T00:12:44Z'",
        "createdHuman: '2262-04-11T23:47:16.854775Z'",
        "createdMachine: soon",  # not a time at all: ignored, as before
        "createdHuman: 13.11.2020",
    ],
)
def test_times_at_the_edges_and_unreadable_ones_are_accepted(line: str) -> None:
    load(f"version: '1.0'\nname: x\n{line}\n")


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("{name: s, min: '5'}", "valid number (got the text '5'; write a number without"),
        ("{name: s, min: 1e3}", "(got the text '1e3'; write a number without quotes, such as"),
        ("{name: s, max: true}", "valid number (got True)"),
        ("{name: s, min: .inf}", "not-a-number and infinite values are not allowed"),
        ("{name: s, max: 1.0e+400}", "not-a-number and infinite values are not allowed"),
        ("{name: s, min: 99999999999999999999}", "does not fit in 64 bits"),
    ],
)
def test_interface_ranges_are_numbers_as_they_will_be_compared(entry: str, message: str) -> None:
    found = problems(f"version: '1.0'\nname: x\ninterface:\n  signals:\n    - {entry}\n")
    assert any(message in text for _, _, text in found), found
    assert all(line == 5 for line, _, _ in found)


def test_interface_flags_are_booleans_not_words() -> None:
    text = (
        "version: '1.0'\nname: x\ninterface:\n  properties:\n    - {name: p, writable: 'no'}\n"
        "  commands:\n    - name: c\n      parameters:\n        - {name: a, required: 'false'}\n"
    )
    assert {(line, path) for line, path, _ in problems(text)} == {
        (5, "interface.properties[0].writable"),
        (9, "interface.commands[0].parameters[0].required"),
    }
    part, _ = load(
        "version: '1.0'\ninterface:\n  signals:\n    - {name: s, min: -1.0e+308, max: 5}\n"
    )
    assert part.interface is not None and part.interface.signals[0].min == -1e308


def test_an_integer_outside_64_bits_has_the_one_message() -> None:
    [(line, path, message)] = problems("version: '1.0'\nname: x\nbig: [1, 12345678901234567890]\n")
    assert (line, path, message) == (3, "big[1]", int64_problem(12345678901234567890))


# Every field a number, a time or a text goes in, with values a hostile or careless author
# might write: validation answers with problems or a document, never with another exception,
# and what it accepts can be stored (JSON without loss) and dated (int64 nanoseconds).
EXTREMES: list[Any] = [
    2**63,
    -(2**63) - 1,
    2**63 - 1,
    10**300,
    1e308,
    -1e308,
    5e-324,
    float("inf"),
    float("nan"),
    "1e400",
    "nan",
    "-inf",
    "",
    " ",
    "x" * 5000,
    "9" * 5000,
    "9999-12-31T23:59:59Z",
    "0001-01-01",
    True,
    None,
    [],
    {},
    [[[[]]]],
    {"a": {"b": [1, {"c": None}]}},
    0,
    -1,
    0.5,
]
FIELDS: list[tuple[str | int, ...]] = [
    ("createdMachine",),
    ("createdHuman",),
    ("modifiedMachine",),
    ("modifiedHuman",),
    ("version",),
    ("privacy",),
    ("id",),
    ("dt-id",),
    ("hosting-iri",),
    ("name",),
    ("slug",),
    ("owner",),
    ("contact",),
    ("location", "gpsCoordinates"),
    ("relations", 0, "relationType"),
    ("relations", 0, "id"),
    ("features", 0, "name"),
    ("features", 0, "keywords"),
    ("interface", "signals", 0, "min"),
    ("interface", "signals", 0, "max"),
    ("interface", "signals", 0, "type"),
    ("interface", "properties", 0, "writable"),
    ("interface", "commands", 0, "parameters", 0, "required"),
    ("interface", "commands", 0, "parameters", 0, "default"),
    ("interface", "unknown_signals"),
]


def _document_with(path: tuple[str | int, ...], value: Any) -> dict[str, Any]:
    doc: dict[str, Any] = {
        "version": "1.0",
        "name": "n",
        "relations": [{"relationType": "parent", "id": "p"}],
        "features": [{"name": "f"}],
        "location": {},
        "interface": {
            "signals": [{"name": "s"}],
            "properties": [{"name": "p"}],
            "commands": [{"name": "c", "parameters": [{"name": "a"}]}],
        },
    }
    node: Any = doc
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return doc


@pytest.mark.parametrize("path", FIELDS, ids=format_path)
def test_no_value_in_any_field_escapes_validation(path: tuple[str | int, ...]) -> None:
    for value in EXTREMES:
        raw = _document_with(path, value)
        try:
            _, stored = validate_part(SourceDocument(raw))
        except DocumentError as err:
            assert err.problems and all(p.message for p in err.problems), (path, value)
            continue
        assert orjson.loads(orjson.dumps(stored)) == stored, (path, value)
        created = imported_created_ns(raw)
        assert created is None or fits_int64(created), (path, value)
