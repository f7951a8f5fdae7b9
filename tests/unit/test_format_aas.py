"""The Asset Administration Shell export and import (formats/aas.py), checked with the
Eclipse BaSyx SDK's own readers and data checker, and with the AAS compliance tool's checks
against the IDTA's official JSON schema."""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import Any

import pytest
import yaml
from aas_compliance_tool import compliance_check_aasx, compliance_check_json
from aas_compliance_tool.state_manager import ComplianceToolStateManager, Status
from basyx.aas import model
from basyx.aas.adapter import aasx
from basyx.aas.adapter.json import json_deserialization, json_serialization
from basyx.aas.examples.data._helper import AASDataChecker

from twinlink.domain.document import Interface, validate_part
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.yamlsource import SourceDocument
from twinlink.formats import _aas_export
from twinlink.formats import _aas_model as m
from twinlink.formats.aas import (
    export_aas,
    export_aasx,
    import_aas,
    import_aasx,
    read_aasx,
    read_json,
    validate_aas,
)
from twinlink.formats.context import ExportContext

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CTX = ExportContext(
    twin_url="https://twins.example/twins/tingen",
    api_url="https://twins.example/api/v1",
    slug="tingen",
    mqtt_url="mqtt://twins.example:1883",
    ws_url="wss://twins.example/api/v1/live",
)


def example(*parts: str) -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load((EXAMPLES.joinpath(*parts)).read_text())
    return data


@pytest.fixture
def tingen() -> dict[str, Any]:
    doc = example("tingen", "tingen.yaml")
    doc["modifiedHuman"] = "2026-11-21T19:10:06.184Z"  # as the document a reader gets has it
    return doc


def compliance(check: Any, path: Path) -> list[str]:
    """The compliance tool's check on a file: the failed steps and what they logged. The tool
    hooks its state into loggers (the SDK's among them) and stops them propagating; their
    state is given back after."""
    names = ["compliance_check", aasx.__name__, json_deserialization.__name__]
    loggers = [logging.getLogger(n) for n in names]
    saved = [(lg.propagate, lg.level, list(lg.handlers)) for lg in loggers]
    state = ComplianceToolStateManager()
    try:
        check(str(path), state)
    finally:
        for lg, (propagate, level, handlers) in zip(loggers, saved, strict=True):
            lg.propagate, lg.handlers = propagate, handlers
            lg.setLevel(level)
    failed = []
    for i, step in enumerate(state.steps):
        if step.status is not Status.SUCCESS:
            logs = [r.getMessage() for r in state.get_error_logs_from_step(i)]
            failed.append(f"{step.name}: {step.status.name} {logs}")
    return failed


def submodel(store: Any, short: str) -> model.Submodel:
    return next(x for x in store if isinstance(x, model.Submodel) and x.id_short == short)


def child(namespace: Any, short: str) -> Any:
    return namespace.get_referable(short)


def same_objects(got: Any, expected: Any) -> None:
    checker = AASDataChecker(raise_immediately=False)
    checker.check_identifiable_store(got, expected)
    assert list(checker.failed_checks) == []
    assert len(list(checker.successful_checks)) > 100  # it did compare the trees


# --- export, checked by the SDK and the compliance tool ------------------------------


def test_json_export_passes_the_official_schema_and_reads_back_as_built(
    tingen: dict[str, Any], tmp_path: Path
) -> None:
    env = export_aas(tingen, CTX)
    path = tmp_path / "tingen.json"
    path.write_text(json.dumps(env))
    assert compliance(compliance_check_json.check_schema, path) == []
    assert compliance(compliance_check_json.check_deserialization, path) == []
    assert validate_aas(env) == []
    same_objects(read_json(env), _aas_export.build(tingen, CTX))


# The compliance tool (1.0.0) makes its store with a class the SDK 2.2 deprecates.
@pytest.mark.filterwarnings("ignore:`DictObjectStore` is deprecated:DeprecationWarning")
def test_aasx_export_passes_the_compliance_tool_and_holds_the_json_export(
    tingen: dict[str, Any], tmp_path: Path
) -> None:
    package = export_aasx(tingen, CTX)
    path = tmp_path / "tingen.aasx"
    path.write_bytes(package)
    assert compliance(compliance_check_aasx.check_deserialization, path) == []
    assert compliance(compliance_check_aasx.check_schema, path) == []
    same_objects(read_aasx(package), read_json(export_aas(tingen, CTX)))


def test_shell_is_named_by_the_dt_id_with_a_submodel_per_template(
    tingen: dict[str, Any],
) -> None:
    store = read_json(export_aas(tingen, CTX))
    shell = next(x for x in store if isinstance(x, model.AssetAdministrationShell))
    assert shell.id == tingen["id"]
    assert shell.asset_information.global_asset_id == tingen["id"]
    assert shell.id_short == "tingen"
    semantics = {
        ref.resolve(store).id_short: ref.resolve(store).semantic_id.key[0].value  # type: ignore[attr-defined]
        for ref in shell.submodel
    }
    assert semantics == {
        "Nameplate": "https://admin-shell.io/idta/nameplate/3/0/Nameplate",
        "ContactInformations": "https://admin-shell.io/zvei/nameplate/1/0/ContactInformations",
        "TechnicalData": "https://admin-shell.io/ZVEI/TechnicalData/Submodel/1/2",
        "OperationalData": "urn:twinlink:aas:OperationalData:1:0",
    }
    nameplate = submodel(store, "Nameplate")
    assert child(nameplate, "URIOfTheProduct").value == tingen["id"]
    assert child(nameplate, "ManufacturerProductDesignation").value["en"] == tingen["name"]


def test_manufacturer_and_owner_go_where_the_templates_have_them() -> None:
    doc = {
        "version": "1.0",
        "id": "https://dt.example/pump-7",
        "name": "Pump 7",
        "manufacturer": {
            "name": "Pumps Oy",
            "email": "sales@pumps.example",
            "website": "https://pumps.example",
        },
        "owner": "Example Lab",
        "contact": {"name": "Bench team", "email": "bench@lab.example"},
    }
    store = read_json(export_aas(doc, CTX))
    nameplate = submodel(store, "Nameplate")
    maker = child(nameplate, "ManufacturerName")
    assert maker.value["en"] == "Pumps Oy"
    assert maker.semantic_id.key[0].value == "0112/2///61987#ABA565#009"
    address = child(nameplate, "AddressInformation")
    assert child(child(address, "Email"), "EmailAddress").value == "sales@pumps.example"
    assert child(address, "AddressOfAdditionalLink").value == "https://pumps.example"
    contacts = submodel(store, "ContactInformations")
    owner = child(contacts, "Owner")
    assert child(owner, "RoleOfContactPerson").value == "owner"
    assert child(owner, "Company").value["en"] == "Example Lab"
    assert child(child(contacts, "Contact"), "NameOfContact").value["en"] == "Bench team"
    general = child(submodel(store, "TechnicalData"), "GeneralInformation")
    assert child(general, "ManufacturerName").value == "Pumps Oy"


def test_operational_data_types_units_ranges_and_operations(tingen: dict[str, Any]) -> None:
    store = read_json(export_aas(tingen, CTX))
    ops = submodel(store, "OperationalData")
    angle = child(child(ops, "Signals"), "Cantilever_Angle_radians")
    assert angle.value_type is model.datatypes.Double
    assert angle.category == "VARIABLE"
    (spec,) = angle.embedded_data_specifications
    assert spec.data_specification_content.unit == "rad"
    assert {q.type: q.value for q in angle.qualifier} == {
        "twinlink:min": "0.0",
        "twinlink:max": "1.0",
    }
    rate = child(child(ops, "Properties"), "sample_rate")
    assert rate.category == "PARAMETER"
    command = child(child(ops, "Commands"), "set_sample_rate")
    assert isinstance(command, model.Operation)
    (value,) = command.input_variable
    assert value.id_short == "value" and value.value_type is model.datatypes.Double
    endpoints = {e.id_short: e.value for e in child(ops, "Endpoints").value}
    assert endpoints == {
        "Twin": CTX.twin_url,
        "Api": "https://twins.example/api/v1/twins/tingen",
        "Live": CTX.ws_url,
        "Mqtt": CTX.mqtt_url,
    }


def test_other_keys_go_to_the_technical_properties_as_a_generic_collection(
    tingen: dict[str, Any],
) -> None:
    store = read_json(export_aas(tingen, CTX))
    technical = child(submodel(store, "TechnicalData"), "TechnicalProperties")
    length = child(child(technical, "physicalProperties"), "length")
    assert child(length, "value").value == tingen["physicalProperties"]["length"]["value"]
    assert child(length, "unit").value == tingen["physicalProperties"]["length"]["unit"]
    further = child(submodel(store, "TechnicalData"), "FurtherInformation")
    assert str(child(further, "ValidDate").value) == "2026-11-21"


def test_a_twin_without_interface_or_manufacturer_still_exports_a_valid_shell() -> None:
    doc = {"version": "1.0", "id": "https://dt.example/bare", "name": "Bare"}
    env = export_aas(doc, CTX)
    assert validate_aas(env) == []
    fragment = import_aas(env)
    assert fragment["interface"] == {"signals": [], "properties": [], "commands": []}
    assert "manufacturer" not in fragment and "owner" not in fragment


def test_a_value_the_metamodel_cannot_hold_is_a_clear_error_not_a_crash() -> None:
    doc = {"version": "1.0", "id": "https://dt.example/" + "x" * 2100}
    with pytest.raises(InvalidInputError, match="cannot be written as an Asset Administration"):
        export_aas(doc, CTX)


# --- import -------------------------------------------------------------------------


def normalised(interface: dict[str, Any]) -> dict[str, Any]:
    return Interface.model_validate(interface).model_dump()


def test_export_then_import_gives_the_same_interface_and_document_fields(
    tingen: dict[str, Any],
) -> None:
    fragment = import_aas(export_aas(tingen, CTX))
    assert normalised(fragment["interface"]) == normalised(tingen["interface"])
    assert fragment["id"] == tingen["id"]
    assert fragment["name"] == tingen["name"]
    assert fragment["description"] == tingen["description"]
    assert fragment["interface"]["default_device"] == tingen["interface"]["default_device"]
    part, _ = validate_part(SourceDocument({"version": "1.0", **fragment}))
    assert part.interface is not None


def test_round_trip_keeps_names_that_are_not_id_shorts_zero_bounds_and_defaults() -> None:
    interface = {
        "signals": [
            {"name": "tip.x", "type": "integer", "min": 0, "max": 10},
            {"name": "tip_x"},  # the idShort "tip.x" is rewritten to
            {"name": "3-phase current", "unit": "A", "min": -0.0},
            {"name": "ok", "type": "bool"},
        ],
        "properties": [{"name": "mode", "type": "string", "writable": False}],
        "commands": [
            {
                "name": "go!",
                "description": "Start.",
                "parameters": [
                    {"name": "speed", "default": 0, "required": False, "min": 0},
                    {"name": "opts", "type": "string", "default": {"a": [1, "b"]}},
                ],
            }
        ],
        "unknown_signals": "reject",
        "out_of_range": "accept",
    }
    doc = {"version": "1.0", "id": "https://dt.example/odd", "interface": interface}
    env = export_aas(doc, CTX)
    assert validate_aas(env) == []
    got = import_aas(env)["interface"]
    assert normalised(got) == normalised(interface)
    assert got["signals"][0]["min"] == 0 and isinstance(got["signals"][0]["min"], int)
    assert got["commands"][0]["parameters"][1]["default"] == {"a": [1, "b"]}


def test_import_reads_manufacturer_owner_and_contact_back_from_a_package() -> None:
    doc = {
        "version": "1.0",
        "id": "https://dt.example/pump-7",
        "name": "Pump 7",
        "description": "A pump.",
        "manufacturer": {"name": "Pumps Oy", "website": "https://pumps.example"},
        "owner": "Example Lab",
        "contact": {"name": "Bench team", "email": "bench@lab.example"},
    }
    fragment = import_aasx(export_aasx(doc, CTX))
    assert fragment == {
        "id": "https://dt.example/pump-7",
        "name": "Pump 7",
        "description": "A pump.",
        "manufacturer": {"name": "Pumps Oy", "website": "https://pumps.example"},
        "owner": "Example Lab",
        "contact": {"name": "Bench team", "email": "bench@lab.example"},
        "interface": {"signals": [], "properties": [], "commands": []},
    }


def third_party_environment() -> dict[str, Any]:
    """A shell another tool wrote: an operational submodel of plain data elements."""
    submodel = model.Submodel(
        "urn:vendor:sm:ops",
        [
            model.Property("Temperature", model.datatypes.Int, 21, category="VARIABLE"),
            model.Property("Setpoint", model.datatypes.Float, 20.5, category="PARAMETER"),
            model.Range("Pressure", model.datatypes.Double, 0.5, 6.0),
            model.Operation(
                "Reset",
                input_variable=[model.Property("delay", model.datatypes.Long)],
            ),
        ],
        id_short="OperationalData",
    )
    shell = model.AssetAdministrationShell(
        model.AssetInformation(global_asset_id="urn:vendor:asset:1"),
        "urn:vendor:aas:1",
        id_short="Heater",
        submodel={model.ModelReference.from_referable(submodel)},
    )
    text = json_serialization.object_store_to_json(model.DictIdentifiableStore([shell, submodel]))
    data: dict[str, Any] = json.loads(text)
    return data


def test_import_of_another_tools_shell_reads_its_data_elements_and_operations() -> None:
    fragment = import_aas(third_party_environment())
    assert fragment["id"] == "urn:vendor:asset:1"
    assert fragment["name"] == "Heater"
    assert fragment["interface"] == {
        "signals": [
            {"name": "Temperature", "type": "integer"},
            {"name": "Setpoint", "type": "number"},
            {"name": "Pressure", "type": "number", "min": 0.5, "max": 6.0},
        ],
        "properties": [],
        "commands": [{"name": "Reset", "parameters": [{"name": "delay", "type": "integer"}]}],
    }
    validate_part(SourceDocument({"version": "1.0", **fragment}))


def test_import_refuses_what_the_document_checks_refuse() -> None:
    env = third_party_environment()
    pressure = env["submodels"][0]["submodelElements"][2]
    pressure["min"], pressure["max"] = "9.0", "1.0"
    with pytest.raises(InvalidInputError) as caught:
        import_aas(env)
    assert "interface.signals[2]: min (9.0) is greater than max (1.0)" in str(caught.value)


# --- validation ---------------------------------------------------------------------


def test_validate_reports_what_the_sdk_refuses_and_dangling_submodels() -> None:
    env = third_party_environment()
    env["submodels"][0]["submodelElements"][0]["idShort"] = "1 bad id"
    env["assetAdministrationShells"][0]["submodels"].append(
        {"type": "ModelReference", "keys": [{"type": "Submodel", "value": "urn:vendor:sm:gone"}]}
    )
    env["extra"] = []
    problems = validate_aas(env)
    assert any("unknown top-level key 'extra'" in p for p in problems)
    assert any("1 bad id" in p for p in problems)
    assert any("urn:vendor:sm:gone" in p and "not in the file" in p for p in problems)
    # The import reads what it can (`twinlink import aas --no-check`): the element the SDK
    # refused is left out, the others come in.
    signals = import_aas(env)["interface"]["signals"]
    assert [s["name"] for s in signals] == ["Setpoint", "Pressure"]


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        ([], "is a JSON object"),
        ({}, "no assetAdministrationShells"),
        ({"submodels": [{"modelType": "Submodel"}]}, "Submodel"),
    ],
)
def test_validate_explains_environments_that_are_not_usable(data: Any, expected: str) -> None:
    problems = validate_aas(data)
    assert problems and any(expected in p for p in problems), problems


def test_an_aasx_that_is_not_a_package_is_refused_with_a_message() -> None:
    with pytest.raises(InvalidInputError, match="not an AASX package"):
        import_aasx(b"PK\x03\x04 not really a zip")


def test_id_shorts_are_valid_and_unique_whatever_the_names() -> None:
    taken: set[str] = set()
    names = ["a.b", "a_b", "A_B", "9lives", "-", "ok-", "x" * 300]
    shorts = [m.id_short(n, taken) for n in names]
    assert shorts[:6] == ["a_b", "a_b_2", "A_B_3", "x9lives", "x_", "ok_"]
    assert shorts[6] == "x" * 128  # the metamodel's longest idShort
    for short in shorts:
        model.Property(short, model.datatypes.String)  # the SDK checks the idShort rules
    assert len({s.lower() for s in shorts}) == len(shorts)
