"""WoT Thing Description 1.1 export and import (formats/wot.py, docs/formats.md): exports
validate against the W3C TD JSON Schema, the specification's example TDs import into
documents twinlink's own checks accept, and interfaces round-trip."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest

from twinlink.domain.document import DocumentPart, Interface, validate_part
from twinlink.domain.yamlsource import SourceDocument, parse_yaml_stream
from twinlink.formats.context import ExportContext
from twinlink.formats.wot import TD_CONTEXT, export_wot, import_wot, validate_wot

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = Path(__file__).parent / "fixtures" / "wot"
SPEC_EXAMPLES = sorted(FIXTURES.glob("*.json"))
CTX = ExportContext(
    twin_url="https://dt.example.org/twins/tingen",
    api_url="https://dt.example.org/api/v1",
    slug="tingen",
    mqtt_url="mqtt://broker.example.org:1883",
    ws_url="wss://dt.example.org/api/v1/live",
    mqtt_topic_prefix="plant/twins",
    mqtt_external=True,
)
PLAIN = ExportContext(
    twin_url="https://dt.example.org/twins/tingen",
    api_url="https://dt.example.org/api/v1",
    slug="tingen",
)


def checked(document: dict[str, Any]) -> tuple[DocumentPart, dict[str, Any]]:
    """twinlink's own document checks, as `POST /api/v1/apply` runs them."""
    return validate_part(SourceDocument(data=copy.deepcopy(document)))


def example(path: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    return data


def tingen() -> dict[str, Any]:
    _, raw = validate_part(parse_yaml_stream((ROOT / "examples/tingen/tingen.yaml").read_text())[0])
    return raw


def interface_of(document: dict[str, Any]) -> dict[str, Any]:
    part, _ = checked({"version": "1.0", **document})
    return (part.interface or Interface()).model_dump()  # none: an empty one


def forms(td: dict[str, Any], kind: str, name: str) -> dict[str, dict[str, Any]]:
    """An affordance's forms by op (the first op of a form that has several)."""
    out = {}
    for form in td[kind][name]["forms"]:
        op = form["op"][0] if isinstance(form["op"], list) else form["op"]
        out[op if not form["href"].startswith("mqtt") else "mqtt"] = form
    return out


def test_the_fixtures_are_the_specification_examples_and_valid() -> None:
    assert len(SPEC_EXAMPLES) >= 7
    for path in SPEC_EXAMPLES:
        assert validate_wot(example(path)) == [], path.name


@pytest.mark.parametrize("path", SPEC_EXAMPLES, ids=lambda p: p.name)
def test_spec_examples_import_export_and_the_export_validates(path: Path) -> None:
    td = example(path)
    fragment = import_wot(td)
    assert fragment["id"] == td["id"]
    assert fragment["name"] == td["title"]
    _, raw = checked({"version": "1.0", **fragment})  # refused with DocumentError otherwise
    exported = export_wot(raw, CTX)
    assert validate_wot(exported) == []
    assert exported["id"] == td["id"] and exported["title"] == td["title"]
    # Every affordance of the example is in the export, under its name.
    names = {n for kind in ("properties", "actions", "events") for n in td.get(kind, {})}
    exported_names = {n for kind in ("properties", "actions", "events") for n in exported[kind]}
    assert names <= exported_names
    # And the export reads back into the same interface: the mapping is a fixed point.
    assert interface_of(import_wot(exported)) == interface_of(fragment)


def test_the_lamp_example_maps_affordance_by_affordance() -> None:
    fragment = import_wot(example(FIXTURES / "td11-lamp-basic.json"))
    assert fragment["interface"] == {
        # A form without `op` reads and writes a property: it is writable.
        "signals": [{"name": "overheating", "type": "string"}],
        "properties": [{"name": "status", "type": "string", "writable": True}],
        "commands": [{"name": "toggle", "parameters": []}],
    }


def test_td_1_0_imports_as_1_1_does() -> None:
    old = import_wot(example(FIXTURES / "td10-lamp.json"))
    new = import_wot(example(FIXTURES / "td11-lamp-basic.json"))
    assert old["interface"] == new["interface"]
    assert old["id"] == "urn:dev:ops:32473-WoTLamp-1234"


def test_data_schemas_inputs_and_kept_keys() -> None:
    interface = import_wot(example(FIXTURES / "td11-data-schemas.json"))["interface"]
    signals = {s["name"]: s for s in interface["signals"]}
    properties = {p["name"]: p for p in interface["properties"]}
    commands = {c["name"]: c for c in interface["commands"]}
    # readOnly and observable: a measured quantity.
    assert signals["temperature"]["unit"] == "degree Celsius"
    assert (signals["temperature"]["min"], signals["temperature"]["max"]) == (-40.0, 125.0)
    assert properties["brightness"] == {
        "name": "brightness",
        "type": "integer",
        "min": 0,
        "max": 100,
        "unit": "percent",
        "description": "Brightness value",
        "writable": True,
    }
    # Read only by its one form's op; its enum is kept on the entry.
    assert properties["mode"]["writable"] is False
    assert properties["mode"]["enum"] == ["on", "off", "eco"]
    # An object property: carried as text, its TD schema kept.
    assert properties["rgb"]["type"] == "string"
    assert properties["rgb"]["schema"]["required"] == ["red", "green", "blue"]
    fade = {p["name"]: p for p in commands["fade"]["parameters"]}
    assert [p["required"] for p in fade.values()] == [False, True, True]
    assert fade["to"]["unit"] == "percent" and fade["to"]["max"] == 100
    assert fade["duration"]["default"] == 1000
    assert commands["fade"]["output"] == {"type": "string"}
    # A scalar input is the command's one argument.
    assert commands["blink"]["parameters"] == [
        {"name": "value", "type": "integer", "min": 1, "max": 10, "required": True}
    ]
    # The event named like the observable property is kept beside the signals.
    assert [e["name"] for e in interface["events"]] == ["temperature"]


def test_tingen_exports_to_a_valid_td_with_real_endpoints() -> None:
    td = export_wot(tingen(), CTX)
    assert validate_wot(td) == []
    assert td["@context"][0] == TD_CONTEXT
    assert td["id"] == "https://twinlink.example/tingen"
    assert td["security"] == ["bearer_sc"]
    assert td["securityDefinitions"]["bearer_sc"]["scheme"] == "bearer"
    # A signal: a read-only, observable property, read from the latest values.
    angle = td["properties"]["Cantilever_Angle_radians"]
    assert (angle["readOnly"], angle["observable"], angle["unit"]) == (True, True, "rad")
    assert (angle["type"], angle["minimum"], angle["maximum"]) == ("number", 0.0, 1.0)
    by_op = forms(td, "properties", "Cantilever_Angle_radians")
    assert by_op["readproperty"]["href"] == (
        "https://dt.example.org/api/v1/twins/tingen/streams/telemetry/latest"
        "?signals=Cantilever_Angle_radians"
    )
    assert by_op["observeproperty"]["href"] == "wss://dt.example.org/api/v1/live"
    assert by_op["mqtt"]["href"] == "mqtt://broker.example.org:1883"
    assert by_op["mqtt"]["mqv:filter"] == "plant/twins/tingen/+/telemetry"
    assert by_op["mqtt"]["security"] == ["broker_sc"]
    # A writable property: PATCH of the desired values, on the default device.
    rate = td["properties"]["sample_rate"]
    assert (rate["readOnly"], rate["observable"]) == (False, False)
    assert rate["uriVariables"]["device"]["default"] == "tingenSAP"
    write = forms(td, "properties", "sample_rate")["writeproperty"]
    assert write["htv:methodName"] == "PATCH"
    assert write["href"].endswith("/twins/tingen/devices/{device}/properties/desired")
    assert td["properties"]["paused"]["readOnly"] is True
    assert "writeproperty" not in forms(td, "properties", "paused")
    # A command: an action whose input is its parameters.
    action = td["actions"]["set_sample_rate"]
    assert action["input"]["required"] == ["value"]
    assert action["input"]["properties"]["value"] == {
        "type": "number",
        "minimum": 1,
        "maximum": 100,
        "unit": "Hz",
    }
    invoke = forms(td, "actions", "set_sample_rate")["invokeaction"]
    assert invoke["href"] == "https://dt.example.org/api/v1/twins/tingen/commands"
    assert "input" not in td["actions"]["pause"]


@pytest.mark.parametrize("mqtt_url", [None, "mqtt://dt.example.org:1883"])
def test_without_an_external_broker_the_export_has_no_mqtt_forms(mqtt_url: str | None) -> None:
    # The embedded listener forwards nothing between clients: no one could observe there.
    ctx = ExportContext(PLAIN.twin_url, PLAIN.api_url, PLAIN.slug, mqtt_url=mqtt_url)
    td = export_wot(tingen(), ctx)
    assert validate_wot(td) == []
    assert "broker_sc" not in td["securityDefinitions"]
    by_op = forms(td, "properties", "Cantilever_Angle_radians")
    assert set(by_op) == {"readproperty", "observeproperty"}
    # Where the twin's devices send is linked: HTTP, the device WebSocket, the listener.
    ingest = [link for link in td["links"] if link["rel"] == "twinlink:deviceIngest"]
    assert [link["href"] for link in ingest] == [
        "https://dt.example.org/api/v1/device/samples",
        "wss://dt.example.org/api/v1/device/ws",
        *([mqtt_url] if mqtt_url else []),
    ]
    if mqtt_url:
        assert ingest[-1]["mqv:topic"] == "twinlink/tingen/{device}/telemetry"
    # The live WebSocket is served beside the API whether or not the caller named it.
    assert by_op["observeproperty"]["href"] == "wss://dt.example.org/api/v1/live"


def test_tingen_round_trips_to_the_same_interface() -> None:
    document = tingen()
    fragment = import_wot(export_wot(document, CTX))
    assert interface_of(fragment) == interface_of(document)
    assert fragment["id"] == document["id"]
    assert (fragment["name"], fragment["description"]) == (
        document["name"],
        document["description"],
    )


@pytest.mark.parametrize("name", ["ilmatar-public", "ilmatar-group", "ilmatar-private", "hall"])
def test_ilmatar_documents_export_validate_and_round_trip(name: str) -> None:
    text = (ROOT / "examples/ilmatar" / f"{name}.yaml").read_text()
    _, document = validate_part(parse_yaml_stream(text)[0])
    td = export_wot(document, PLAIN)
    assert validate_wot(td) == []
    assert interface_of(import_wot(td)) == interface_of(document)


def test_a_signal_named_like_a_property_is_an_event_and_round_trips() -> None:
    document = {
        "version": "1.0",
        "name": "pump",
        "interface": {
            "signals": [{"name": "speed", "unit": "rpm", "type": "integer"}],
            "properties": [{"name": "speed", "type": "integer", "writable": True}],
            "unknown_signals": "reject",
        },
    }
    td = export_wot(document, PLAIN)
    assert validate_wot(td) == []
    assert td["events"]["speed"]["data"] == {"type": "integer", "unit": "rpm"}
    assert td["properties"]["speed"]["readOnly"] is False
    assert interface_of(import_wot(td)) == interface_of(document)


def test_validate_reports_schema_and_security_problems() -> None:
    td = example(FIXTURES / "td11-lamp-basic.json")
    del td["title"]
    td["security"] = ["missing_sc"]
    td["properties"]["status"]["forms"][0]["op"] = "invokeaction"
    problems = validate_wot(td)
    assert any("'title' is a required property" in p for p in problems), problems
    assert any(p.startswith("properties/status/forms/0/op") for p in problems), problems
    assert "security: security scheme 'missing_sc' is not in securityDefinitions" in problems


def test_what_is_not_a_td_object_is_refused() -> None:
    assert validate_wot([]) == ["(the TD): [] is not of type 'object'"]  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="JSON object"):
        import_wot([])  # type: ignore[arg-type]
