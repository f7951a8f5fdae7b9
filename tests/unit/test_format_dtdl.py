"""DTDL v3: export of a twin's interface, import of published and exported Interfaces, and
validate_dtdl, one test per rule of the specification it checks (a valid case and a broken
one each)."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from twinlink.domain.document import Interface, validate_part
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.yamlsource import SourceDocument, parse_yaml_stream
from twinlink.formats._dtdl_check import DTMI
from twinlink.formats.context import ExportContext
from twinlink.formats.dtdl import dtmi_for, export_dtdl, import_dtdl, validate_dtdl

FIXTURES = Path(__file__).parent / "fixtures" / "dtdl"
EXAMPLES = Path(__file__).parents[2] / "examples"
CTX = ExportContext(
    twin_url="http://127.0.0.1:8000/twins/crane",
    api_url="http://127.0.0.1:8000/api/v1",
    slug="crane",
)

DOCUMENT: dict[str, Any] = {
    "version": "1.0",
    "id": "http://d-t.fi/ilmatar-K16052",
    "name": "Ilmatar crane",
    "description": "An overhead crane.",
    "relations": [
        {"relationType": "parent", "id": "http://d-t.fi/aalto-industrial-hall"},
        {"relationType": "child", "dt-id": "https://dtid.org/hoist-1"},
        {"relationType": "child", "id": "https://dtid.org/trolley-1"},
    ],
    "interface": {
        "signals": [
            {"name": "angle", "unit": "rad", "min": 0.0, "max": 1.0, "description": "Tip."},
            {"name": "temp-1", "unit": "°C"},
            {"name": "load", "unit": "kN", "type": "number"},
            {"name": "count", "type": "integer"},
            {"name": "ok", "type": "bool"},
            {"name": "state", "type": "string"},
        ],
        "properties": [
            {"name": "sample_rate", "unit": "Hz", "min": 1, "max": 100, "writable": True},
            {"name": "count", "type": "integer"},
        ],
        "commands": [
            {"name": "pause", "description": "Stop sending.", "parameters": []},
            {
                "name": "set_sample_rate",
                "parameters": [{"name": "value", "unit": "Hz", "min": 1, "required": True}],
            },
            {
                "name": "move",
                "parameters": [
                    {"name": "x", "unit": "m", "required": True},
                    {"name": "2nd axis", "unit": "m", "default": 0},
                ],
            },
        ],
        "unknown_signals": "drop",
        "out_of_range": "accept",
    },
}


def checked(fragment: dict[str, Any]) -> dict[str, Any]:
    """The fragment as twinlink's document checks read it (they raise on a problem)."""
    part, _ = validate_part(SourceDocument({"version": "1.0", **fragment}))
    assert part.interface is not None
    return part.interface.model_dump(by_alias=True)


def normal(interface: dict[str, Any]) -> dict[str, Any]:
    return Interface.model_validate(interface).model_dump(by_alias=True)


# -- export ---------------------------------------------------------------------------------


def test_export_is_a_valid_dtdl_v3_interface() -> None:
    out = export_dtdl(DOCUMENT, CTX)
    assert validate_dtdl(out) == []
    assert out["@context"] == ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1"]
    assert out["@type"] == "Interface"
    assert out["@id"] == dtmi_for("http://d-t.fi/ilmatar-K16052")
    assert out["displayName"] == "Ilmatar crane"
    assert out["description"] == "An overhead crane."
    kinds = [c["@type"] if isinstance(c["@type"], str) else c["@type"][0] for c in out["contents"]]
    assert kinds == ["Telemetry"] * 6 + ["Property"] * 2 + ["Command"] * 3 + ["Relationship"] * 3


def test_export_maps_types_units_and_writable() -> None:
    contents = {c["name"]: c for c in export_dtdl(DOCUMENT, CTX)["contents"]}
    assert contents["angle"]["@type"] == ["Telemetry", "Angle"]
    assert contents["angle"]["unit"] == "radian"
    assert contents["angle"]["schema"] == "double"
    assert contents["temp_1"]["unit"] == "degreeCelsius"
    # kN has no DTDL unit: no semantic type, the symbol kept in the note
    assert contents["load"]["@type"] == "Telemetry" and "unit" not in contents["load"]
    assert '"unit":"kN"' in contents["load"]["comment"]
    assert contents["count"]["schema"] == "long"
    assert contents["ok"]["schema"] == "boolean"
    assert contents["state"]["schema"] == "string"
    assert contents["sample_rate"]["writable"] is True
    assert contents["count_2"]["writable"] is False  # the property `count`, renamed: unique


def test_export_commands_one_request_or_an_object_of_fields() -> None:
    contents = {c["name"]: c for c in export_dtdl(DOCUMENT, CTX)["contents"]}
    assert "request" not in contents["pause"]
    one = contents["set_sample_rate"]["request"]
    assert one["name"] == "value" and one["unit"] == "hertz"
    several = contents["move"]["request"]
    assert several["schema"]["@type"] == "Object"
    assert [f["name"] for f in several["schema"]["fields"]] == ["x", "n_2nd_axis"]


def test_export_relations_target_the_other_twins_dtmi() -> None:
    relationships = [
        c for c in export_dtdl(DOCUMENT, CTX)["contents"] if c["@type"] == "Relationship"
    ]
    assert [r["name"] for r in relationships] == ["parent", "child", "child_2"]
    assert relationships[0]["target"] == dtmi_for("http://d-t.fi/aalto-industrial-hall")
    assert relationships[1]["target"] == dtmi_for("https://dtid.org/hoist-1")
    # the hall's own export has the DTMI this relation targets
    hall = export_dtdl({"id": "http://d-t.fi/aalto-industrial-hall", "name": "Hall"}, CTX)
    assert hall["@id"] == relationships[0]["target"]


def test_export_without_units_has_only_the_dtdl_context() -> None:
    out = export_dtdl({"id": "x", "interface": {"signals": [{"name": "a"}]}}, CTX)
    assert out["@context"] == "dtmi:dtdl:context;3"
    assert validate_dtdl(out) == []


def test_export_of_a_document_without_interface_or_id() -> None:
    out = export_dtdl({"version": "1.0", "name": "Bare"}, CTX)
    assert out["@id"] == dtmi_for(CTX.twin_url)
    assert out["contents"] == []
    assert validate_dtdl(out) == []


@pytest.mark.parametrize(
    "global_id",
    [
        "http://d-t.fi/ilmatar-K16052",
        "https://dtid.org/2f3c8e5a-7c2d-4d2b-9c46-0a4f7f5b1f10",
        "urn:uuid:123",
        "1-2-3",
        "---",
        "http://example.org/" + "segment/" * 60,
        "ä/ö/ü",
    ],
)
def test_dtmi_is_valid_short_and_stable(global_id: str) -> None:
    dtmi = dtmi_for(global_id)
    assert DTMI.match(dtmi) and len(dtmi) <= 128
    assert not dtmi.startswith(("dtmi:dtdl:", "dtmi:standard:"))
    assert dtmi == dtmi_for(global_id)


def test_dtmis_of_ids_that_read_alike_differ() -> None:
    assert dtmi_for("http://x.org/a-b") != dtmi_for("http://x.org/a_b")
    assert dtmi_for("http://x.org/a-b").startswith("dtmi:org:x:a_b:h")


def test_tingen_example_exports_valid() -> None:
    docs = parse_yaml_stream((EXAMPLES / "tingen" / "tingen.yaml").read_text())
    for doc in docs:
        assert validate_dtdl(export_dtdl(doc.data, CTX)) == []


# -- import ---------------------------------------------------------------------------------


def test_round_trip_gives_the_same_interface_and_relations() -> None:
    fragment = import_dtdl(export_dtdl(DOCUMENT, CTX))
    assert checked(fragment) == normal(DOCUMENT["interface"])
    assert fragment["id"] == DOCUMENT["id"]
    assert fragment["name"] == "Ilmatar crane"
    assert fragment["description"] == "An overhead crane."
    assert fragment["relations"] == [
        {"relationType": "parent", "id": "http://d-t.fi/aalto-industrial-hall"},
        {"relationType": "child", "id": "https://dtid.org/hoist-1"},
        {"relationType": "child", "id": "https://dtid.org/trolley-1"},
    ]


def test_a_long_name_is_cut_in_display_name_and_imports_whole() -> None:
    name = "A crane with a name longer than sixty-four characters, as some have"
    out = export_dtdl({"id": "http://x.org/c", "name": name}, CTX)
    assert out["displayName"] == name[:64]
    assert validate_dtdl(out) == []
    assert import_dtdl(out)["name"] == name


def test_round_trip_of_the_tingen_example() -> None:
    for doc in parse_yaml_stream((EXAMPLES / "tingen" / "tingen.yaml").read_text()):
        if isinstance(doc.data.get("interface"), dict):
            fragment = import_dtdl(export_dtdl(doc.data, CTX))
            assert checked(fragment) == normal(doc.data["interface"])


@pytest.mark.parametrize("path", sorted(FIXTURES.glob("*.json")), ids=lambda p: p.name)
def test_published_examples_import(path: Path) -> None:
    fragment = import_dtdl(json.loads(path.read_text()))
    checked(fragment)  # twinlink's document checks accept it
    assert fragment["name"]


def test_published_examples_validate() -> None:
    for path in sorted(FIXTURES.glob("*.json")):
        assert validate_dtdl(json.loads(path.read_text())) == [], path.name


def test_import_of_the_quantitative_types_example() -> None:
    fragment = import_dtdl(json.loads((FIXTURES / "v3-sensor-quantitative.json").read_text()))
    signals = {s["name"]: s for s in fragment["interface"]["signals"]}
    assert signals["thermometer"] == {"name": "thermometer", "unit": "°C", "type": "number"}
    assert signals["barometer"]["unit"] == "mbar"
    assert signals["humidityMeter"] == {"name": "humidityMeter", "unit": "%", "type": "integer"}
    assert signals["anemometer"]["unit"] == "m/s"


def test_import_of_a_v2_interface() -> None:
    fragment = import_dtdl(json.loads((FIXTURES / "v2-thermostat-1.json").read_text()))
    interface = fragment["interface"]
    assert fragment["name"] == "Thermostat"
    assert [s["name"] for s in interface["signals"]] == ["temperature"]
    assert interface["signals"][0]["unit"] == "°C"
    props = {p["name"]: p["writable"] for p in interface["properties"]}
    assert props == {"targetTemperature": True, "maxTempSinceLastReboot": False}
    (command,) = interface["commands"]
    assert command["parameters"] == [
        {
            "name": "since",
            "type": "string",
            "dtdlSchema": "dateTime",
            "description": "Period to return the max-min report.",
        }
    ]
    assert command["dtdlResponse"]["name"] == "tempReport"
    assert "id" not in fragment  # a DTMI names a model, not a twin


def test_import_keeps_what_twinlink_cannot_type() -> None:
    fragment = import_dtdl(json.loads((FIXTURES / "v3-building.json").read_text()))
    (other,) = fragment["interface"]["dtdlOther"]
    assert other["@type"] == "Relationship" and other["name"] == "contains"
    assert "relations" not in fragment  # a Relationship of a model links kinds, not twins
    interface = {
        "@context": "dtmi:dtdl:context;3",
        "@id": "dtmi:ex:a;1",
        "@type": "Interface",
        "contents": [
            {"@type": "Telemetry", "name": "pos", "schema": "point"},
            {"@type": "Component", "name": "camera", "schema": "dtmi:ex:camera;1"},
        ],
    }
    assert [o["name"] for o in import_dtdl(interface)["interface"]["dtdlOther"]] == [
        "pos",
        "camera",
    ]


def test_import_of_localized_texts_and_an_enum() -> None:
    interface = {
        "@context": "dtmi:dtdl:context;3",
        "@id": "dtmi:ex:fan;1",
        "@type": "Interface",
        "displayName": {"it": "Ventilatore", "en": "Fan"},
        "contents": [
            {
                "@type": "Property",
                "name": "mode",
                "schema": {
                    "@type": "Enum",
                    "valueSchema": "string",
                    "enumValues": [
                        {"name": "low", "enumValue": "low"},
                        {"name": "high", "enumValue": "high"},
                    ],
                },
            }
        ],
    }
    fragment = import_dtdl(interface)
    assert fragment["name"] == "Fan"
    assert fragment["interface"]["properties"][0]["enum"] == ["low", "high"]
    checked(fragment)


@pytest.mark.parametrize(
    "data",
    [{"@type": "Telemetry", "name": "x"}, [], [{"@type": "Interface"}, {"@type": "Interface"}]],
)
def test_import_refuses_what_is_not_one_interface(data: Any) -> None:
    with pytest.raises(InvalidInputError, match="Interface"):
        import_dtdl(data)


# -- validate_dtdl: one rule a case, valid and broken -----------------------------------------

BASE: dict[str, Any] = {
    "@context": ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1"],
    "@id": "dtmi:com:example:Crane;1",
    "@type": "Interface",
    "displayName": "Crane",
    "contents": [
        {
            "@type": ["Telemetry", "Temperature"],
            "name": "temp",
            "schema": "double",
            "unit": "kelvin",
        },
        {"@type": "Property", "name": "rate", "schema": "double", "writable": True},
        {
            "@type": "Command",
            "name": "move",
            "request": {"name": "to", "schema": "double"},
            "response": {"name": "done", "schema": "boolean"},
        },
        {"@type": "Relationship", "name": "parent", "target": "dtmi:com:example:Hall;1"},
    ],
}

# An edit changes the model in place, or returns the model to check instead (a list).
Edit = Callable[[dict[str, Any]], Any]


def _set(path: str, value: Any) -> Edit:
    """An edit that sets the value at a dotted path (`contents.0.name`) of the model."""

    def edit(model: dict[str, Any]) -> None:
        *parents, last = path.split(".")
        node: Any = model
        for key in parents:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value

    return edit


def _drop(path: str) -> Edit:
    def edit(model: dict[str, Any]) -> None:
        *parents, last = path.split(".")
        node: Any = model
        for key in parents:
            node = node[int(key)] if isinstance(node, list) else node[key]
        del node[last]

    return edit


def _add_content(element: dict[str, Any]) -> Edit:
    return lambda model: model["contents"].append(element)


def _beside(edit: Edit, name: str) -> Edit:
    """The edit, and the model as a list with the Interface `name` defined beside it."""

    def model(base: dict[str, Any]) -> list[dict[str, Any]]:
        edit(base)
        return [base, {"@context": "dtmi:dtdl:context;3", **_inner(name)}]

    return model


def _inner(name: str) -> dict[str, Any]:
    """An Interface defined inline (a reference to one outside the model is incomplete)."""
    return {"@id": f"dtmi:com:example:{name};1", "@type": "Interface"}


def _plain_context(model: dict[str, Any]) -> None:
    """The DTDL context alone, as a string: the model then has no semantic types."""
    model["@context"] = "dtmi:dtdl:context;3"
    model["contents"][0] = {"@type": "Telemetry", "name": "temp", "schema": "double"}


def _nested_arrays(depth: int) -> dict[str, Any]:
    schema: Any = "double"
    for _ in range(depth):
        schema = {"@type": "Array", "elementSchema": schema}
    return {"@type": "Telemetry", "name": "deep", "schema": schema}


# (rule, an edit that keeps the model valid, an edit that breaks the rule, the message's words)
RULES: list[tuple[str, Edit, Edit, str]] = [
    (
        "context required at the top",
        _plain_context,
        _drop("@context"),
        'needs "@context"',
    ),
    (
        "context is a DTDL version",
        _plain_context,
        _set("@context", "dtmi:dtdl:context;9"),
        "this checker knows DTDL v3 and v2",
    ),
    (
        "context values are versioned DTMIs",
        _set("@context", ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1"]),
        _set("@context", ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes"]),
        "is not a DTMI with a version",
    ),
    (
        "the DTDL context comes first",
        _set("@context", ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1"]),
        _set("@context", ["dtmi:dtdl:extension:quantitativeTypes;1", "dtmi:dtdl:context;3"]),
        "must come before the extensions",
    ),
    (
        "the top is an Interface",
        _set("@type", "dtmi:dtdl:class:Interface;3"),
        _set("@type", "Telemetry"),
        "must include one of Interface",
    ),
    (
        "an Interface has an @id",
        _set("@id", "dtmi:com:example:Crane;2"),
        _drop("@id"),
        "needs `@id`",
    ),
    (
        "@id is a DTMI",
        _set("@id", "dtmi:com:example:Crane;1.5"),
        _set("@id", "dtmi:com:example:9Crane;1"),
        "is not a DTMI",
    ),
    (
        "DTMI versions have no leading zero",
        _set("@id", "dtmi:com:example:Crane"),
        _set("@id", "dtmi:com:example:Crane;01"),
        "is not a DTMI",
    ),
    (
        "an Interface DTMI has at most 128 characters",
        _set("@id", "dtmi:" + "a" * 121 + ";1"),
        _set("@id", "dtmi:" + "a" * 122 + ";1"),
        "at most 128 characters",
    ),
    (
        "other DTMIs have at most 2048 characters",
        _set("contents.0.@id", "dtmi:" + "a" * 2041 + ";1"),
        _set("contents.0.@id", "dtmi:" + "a" * 2042 + ";1"),
        "at most 2048 characters",
    ),
    (
        "reserved DTMI prefixes",
        _set("@id", "dtmi:dtdlx:Crane;1"),
        _set("@id", "dtmi:dtdl:Crane;1"),
        "are reserved",
    ),
    (
        "no duplicate @id",
        _set("contents.0.@id", "dtmi:com:example:Crane:temp;1"),
        _set("contents.0.@id", "dtmi:com:example:Crane;1"),
        "is used twice",
    ),
    (
        "name pattern",
        _set("contents.0.name", "temp_2b"),
        _set("contents.0.name", "temp_"),
        "letters, digits and _",
    ),
    (
        "name starts with a letter",
        _set("contents.0.name", "t1"),
        _set("contents.0.name", "1t"),
        "letters, digits and _",
    ),
    (
        "name length",
        _set("contents.0.name", "t" * 512),
        _set("contents.0.name", "t" * 513),
        "at most 512 characters",
    ),
    (
        "names unique in contents",
        _set("contents.1.name", "rate2"),
        _set("contents.1.name", "temp"),
        "is used twice in the contents",
    ),
    (
        "displayName length",
        _set("displayName", "c" * 512),  # the specification's limit, and DTDLParser's
        _set("displayName", "c" * 513),
        "at most 512 characters",
    ),
    (
        "description length",
        _set("description", "d" * 512),
        _set("description", "d" * 513),
        "at most 512 characters",
    ),
    (
        "comment length",
        _set("comment", "c" * 512),
        _set("comment", "c" * 513),
        "at most 512 characters",
    ),
    (
        "localizable string language codes",
        _set("description", {"en": "a", "fi-FI": "b"}),
        _set("description", {"english": "a"}),
        "must be a string or a language map",
    ),
    (
        "comment is not localizable",
        _set("comment", "plain"),
        _set("comment", {"en": "x"}),
        "must be a string",
    ),
    (
        "required members",
        _set("contents.1.schema", "float"),
        _drop("contents.1.schema"),
        "a Property needs `schema`",
    ),
    (
        "members allowed per element",
        _set("contents.1.writable", False),
        _set("contents.1.target", "dtmi:x;1"),
        "a Property has no member `target`",
    ),
    (
        "no other @ keywords",
        _set("contents.1.@id", "dtmi:com:example:rate;1"),
        _set("contents.1.@language", "en"),
        "@language is not allowed",
    ),
    (
        "member names with ':' are DTMIs",
        _set("contents.1.dtmi:dtdl:property:comment;3", "c"),
        _set("contents.1.ex:note", "c"),
        "with ':' must be a DTMI",
    ),
    (
        "a member is not given as a term and a DTMI both",
        _set("contents.1.comment", "c"),
        _set("contents.1.dtmi:dtdl:property:name;3", "rate"),
        "is given twice",
    ),
    (
        "contents hold content elements",
        _add_content({"@type": "Component", "name": "c", "schema": _inner("Camera")}),
        _add_content({"@type": "Object", "fields": []}),
        "must include one of Command",
    ),
    (
        "@type values are terms or DTMIs",
        _set("contents.1.@type", "dtmi:dtdl:class:Property;3"),
        _set("contents.1.@type", ["Property", "ex:Flavor"]),
        "neither a DTDL term nor a DTMI",
    ),
    (
        "undefined co-types",
        _set("contents.0.@type", ["Telemetry", "Temperature"]),
        _set("contents.0.@type", ["Telemetry", "Flavor"]),
        "'Flavor' is not defined",
    ),
    (
        "semantic types need the QuantitativeTypes context",
        _set("contents.0.unit", "kelvin"),
        _set("@context", "dtmi:dtdl:context;3"),
        "add dtmi:dtdl:extension:quantitativeTypes;1",
    ),
    (
        "a semantic type's unit is of its unit type",
        _set("contents.0.unit", "degreeFahrenheit"),
        _set("contents.0.unit", "metre"),
        "needs a unit of TemperatureUnit",
    ),
    (
        "a semantic type needs a numeric schema",
        _set("contents.0.schema", "integer"),
        _set("contents.0.schema", "string"),
        "needs a numeric schema",
    ),
    (
        "unit only with a semantic type",
        _set("contents.0.unit", "kelvin"),
        _set("contents.1.unit", "kelvin"),
        "has no member `unit`",
    ),
    (
        "an unknown extension is reported",
        _set("@context", ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1"]),
        _set(
            "@context",
            ["dtmi:dtdl:context;3", "dtmi:dtdl:extension:quantitativeTypes;1", "dtmi:ex:flavors;1"],
        ),
        "an extension this checker does not know",
    ),
    (
        "schemas are standard or defined",
        _set("contents.1.schema", "dateTime"),
        _set("contents.1.schema", "decimal"),
        "is not a DTDL schema",
    ),
    (
        "a schema reference is defined in the model",
        lambda m: m.update(
            schemas=[{"@id": "dtmi:com:example:v;1", "@type": "Array", "elementSchema": "double"}],
            contents=[{"@type": "Property", "name": "v", "schema": "dtmi:com:example:v;1"}],
        ),
        _set("contents.1.schema", "dtmi:com:example:v;1"),
        "is not defined in this model",
    ),
    (
        "a Component's Interface is defined in the model",
        _beside(
            _add_content({"@type": "Component", "name": "c", "schema": "dtmi:com:example:Cam;1"}),
            "Cam",
        ),
        _add_content({"@type": "Component", "name": "c", "schema": "dtmi:com:example:Cam;1"}),
        "dtmi:com:example:Cam;1 is not defined in this model",
    ),
    (
        "an extended Interface is defined in the model",
        _beside(_set("extends", "dtmi:com:example:Base;1"), "Base"),
        _set("extends", "dtmi:com:example:Base;1"),
        "dtmi:com:example:Base;1 is not defined in this model",
    ),
    (
        "a schema in `schemas` has an @id",
        _set("schemas", [{"@id": "dtmi:com:example:s;1", "@type": "Object", "fields": []}]),
        _set("schemas", [{"@type": "Object", "fields": []}]),
        "needs an @id",
    ),
    (
        "writable is a boolean",
        _set("contents.1.writable", False),
        _set("contents.1.writable", "true"),
        "must be true or false",
    ),
    (
        "a Command has one request",
        _set("contents.2.request", [{"name": "to", "schema": "double"}]),
        _set(
            "contents.2.request",
            [{"name": "a", "schema": "double"}, {"name": "b", "schema": "double"}],
        ),
        "has one request",
    ),
    (
        "a request has a name and a schema",
        _set(
            "contents.2.request",
            {
                "name": "to",
                "schema": {"@type": "Object", "fields": [{"name": "x", "schema": "double"}]},
            },
        ),
        _set("contents.2.request", {"schema": "double"}),
        "a CommandRequest needs `name`",
    ),
    (
        "a response has a schema",
        _set("contents.2.response", {"name": "ok", "schema": "string"}),
        _set("contents.2.response", {"name": "ok"}),
        "a CommandResponse needs `schema`",
    ),
    (
        "a request's @type, when given",
        _set("contents.2.request.@type", "CommandRequest"),
        _set("contents.2.request.@type", "CommandResponse"),
        "must include one of CommandRequest",
    ),
    (
        "a Relationship's target is a DTMI",
        _set("contents.3.target", "dtmi:com:example:Room;2"),
        _set("contents.3.target", "http://example.org/room"),
        "must be a DTMI",
    ),
    (
        "minMultiplicity is 0",
        _set("contents.3.minMultiplicity", 0),
        _set("contents.3.minMultiplicity", 1),
        "must be 0 in DTDL v3",
    ),
    (
        "maxMultiplicity at least 1",
        _set("contents.3.maxMultiplicity", 1),
        _set("contents.3.maxMultiplicity", 0),
        "an integer of at least 1",
    ),
    (
        "Relationship properties unique",
        _set(
            "contents.3.properties",
            [
                {"@type": "Property", "name": "a", "schema": "double"},
                {"@type": "Property", "name": "b", "schema": "double"},
            ],
        ),
        _set(
            "contents.3.properties",
            [
                {"@type": "Property", "name": "a", "schema": "double"},
                {"@type": "Property", "name": "a", "schema": "double"},
            ],
        ),
        "is used twice in the properties",
    ),
    (
        "Object field names unique",
        _set(
            "contents.1.schema",
            {
                "@type": "Object",
                "fields": [{"name": "x", "schema": "double"}, {"name": "y", "schema": "double"}],
            },
        ),
        _set(
            "contents.1.schema",
            {
                "@type": "Object",
                "fields": [{"name": "x", "schema": "double"}, {"name": "x", "schema": "double"}],
            },
        ),
        "is used twice in the fields",
    ),
    (
        "Enum value schema and values",
        _set(
            "contents.1.schema",
            {
                "@type": "Enum",
                "valueSchema": "integer",
                "enumValues": [{"name": "off", "enumValue": 0}, {"name": "on", "enumValue": 1}],
            },
        ),
        _set(
            "contents.1.schema",
            {
                "@type": "Enum",
                "valueSchema": "integer",
                "enumValues": [{"name": "off", "enumValue": "0"}],
            },
        ),
        "must be integer as valueSchema says",
    ),
    (
        "Enum values unique",
        _set(
            "contents.1.schema",
            {
                "@type": "Enum",
                "valueSchema": "string",
                "enumValues": [{"name": "a", "enumValue": "a"}, {"name": "b", "enumValue": "b"}],
            },
        ),
        _set(
            "contents.1.schema",
            {
                "@type": "Enum",
                "valueSchema": "string",
                "enumValues": [{"name": "a", "enumValue": "a"}, {"name": "b", "enumValue": "a"}],
            },
        ),
        "is given twice",
    ),
    (
        "a Map's key is a string",
        _set(
            "contents.1.schema",
            {
                "@type": "Map",
                "mapKey": {"name": "k", "schema": "string"},
                "mapValue": {"name": "v", "schema": "double"},
            },
        ),
        _set(
            "contents.1.schema",
            {
                "@type": "Map",
                "mapKey": {"name": "k", "schema": "integer"},
                "mapValue": {"name": "v", "schema": "double"},
            },
        ),
        'schema must be "string"',
    ),
    (
        "schemas nest at most 5 deep",
        _add_content(_nested_arrays(5)),
        _add_content(_nested_arrays(6)),
        "nest more than 5 levels",
    ),
    (
        "a Component's schema is an Interface",
        _add_content(
            {
                "@type": "Component",
                "name": "c",
                "schema": {"@id": "dtmi:com:example:Inner;1", "@type": "Interface"},
            }
        ),
        _add_content({"@type": "Component", "name": "c", "schema": "double"}),
        "a Component's schema is an Interface",
    ),
    (
        "extends takes DTMIs or Interfaces",
        _set("extends", _inner("Base")),
        _set("extends", "Base"),
        "`extends` takes DTMIs or Interfaces",
    ),
    (
        "extends at most 1024 Interfaces",
        _set("extends", [_inner(f"B{i}") for i in range(1024)]),
        _set("extends", [_inner(f"B{i}") for i in range(1025)]),
        "more than 1024 Interfaces",
    ),
    (
        "at most 100000 elements",
        lambda m: m["contents"].extend(_fields(20_000)),  # 1 MiB is reached first
        lambda m: m["contents"].extend(_fields(100_000)),
        "DTDL allows 100000",
    ),
    (
        "an Interface is at most 1 MiB",
        _set("contents.1.comment", "c"),
        lambda m: m["contents"].extend(
            {"@type": "Telemetry", "name": f"t{i}", "description": "d" * 500, "schema": "double"}
            for i in range(2200)
        ),
        "DTDL allows 1 MiB",
    ),
]


def _fields(count: int) -> list[dict[str, Any]]:
    """One Telemetry whose Object has count - 2 fields: count elements under contents."""
    fields = [{"name": f"f{i}", "schema": "double"} for i in range(count - 2)]
    return [{"@type": "Telemetry", "name": "many", "schema": {"@type": "Object", "fields": fields}}]


def test_base_model_is_valid() -> None:
    assert validate_dtdl(copy.deepcopy(BASE)) == []


@pytest.mark.parametrize(
    ("valid", "broken", "words"), [r[1:] for r in RULES], ids=[r[0] for r in RULES]
)
def test_rule(valid: Edit, broken: Edit, words: str) -> None:
    good: Any = copy.deepcopy(BASE)
    good = valid(good) or good
    assert validate_dtdl(good) == []
    bad = copy.deepcopy(BASE)
    broken(bad)
    problems = validate_dtdl(bad)
    assert any(words in p for p in problems), problems


def test_a_model_is_an_object_or_an_array_of_them() -> None:
    assert validate_dtdl([copy.deepcopy(BASE)]) == []
    assert validate_dtdl([1]) == [
        "a DTDL model is a JSON object (an Interface) or an array of them"
    ]


def test_ids_are_unique_across_the_interfaces_of_a_model() -> None:
    problems = validate_dtdl([copy.deepcopy(BASE), copy.deepcopy(BASE)])
    assert any(
        "[1].@id: @id dtmi:com:example:Crane;1 is used twice (first at [0].@id)" in p
        for p in problems
    )


def test_problems_name_the_path() -> None:
    bad = copy.deepcopy(BASE)
    bad["contents"][2]["request"]["schema"] = "decimal"
    assert validate_dtdl(bad) == [
        "contents[2].request.schema: 'decimal' is not a DTDL schema (double, string, ...) or a DTMI"
    ]


def test_dtdl_v2_models_are_checked_by_v2s_differences() -> None:
    v2 = json.loads((FIXTURES / "v2-thermostat-1.json").read_text())
    v2["contents"][3]["request"]["@type"] = "CommandPayload"  # v2's name for a request
    assert validate_dtdl(v2) == []  # semantic types built in, no extension context
    v2["contents"][0]["name"] = "t" * 65
    assert validate_dtdl(v2) == ["contents[0].name: at most 64 characters, not 65"]
    v3 = copy.deepcopy(BASE)
    v3["contents"][2]["request"]["@type"] = "CommandPayload"
    assert validate_dtdl(v3) == ["contents[2].request.@type: must include one of CommandRequest"]
