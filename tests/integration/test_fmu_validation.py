"""An fmu processor its FMU cannot run is refused at create and update (422 naming the variable
and the reason), from what the upload's inspection kept, instead of crash-looping later.

The typed FMUs are the built test FMUs (status: FMI 2, tingen3: FMI 3) with a modelDescription
declaring variables of every type: inspected at upload as any FMU is, never run here.
"""

from __future__ import annotations

import zipfile
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FmuFiles, Server
from tests.integration._live import device_twin
from tests.integration._processors import create, processor
from tests.integration._processors import server as server  # module fixture
from tests.integration._util import unique
from tests.integration.test_fmu_processors import upload
from tests.integration.test_processors_libref import push_fmu

pytestmark = pytest.mark.integration

FMI2_TYPED = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="status"
  guid="{0f3b7c6d-2e1a-4b9c-8d7e-6a5b4c3d2e03}" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="status" canHandleVariableCommunicationStepSize="true"/>
  <TypeDefinitions>
    <SimpleType name="Mode"><Enumeration>
      <Item name="off" value="0"/><Item name="slow" value="1"/><Item name="fast" value="5"/>
    </Enumeration></SimpleType>
  </TypeDefinitions>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="0" causality="input" variability="continuous">
      <Real start="0"/></ScalarVariable>
    <ScalarVariable name="y" valueReference="1" causality="output" variability="continuous"
      initial="calculated"><Real/></ScalarVariable>
    <ScalarVariable name="n" valueReference="2" causality="input" variability="discrete">
      <Integer start="0"/></ScalarVariable>
    <ScalarVariable name="count" valueReference="3" causality="parameter" variability="fixed">
      <Integer start="1" min="0" max="10"/></ScalarVariable>
    <ScalarVariable name="big" valueReference="4" causality="parameter" variability="fixed">
      <Integer start="1"/></ScalarVariable>
    <ScalarVariable name="on" valueReference="5" causality="parameter" variability="fixed">
      <Boolean start="false"/></ScalarVariable>
    <ScalarVariable name="mode" valueReference="6" causality="parameter" variability="fixed">
      <Enumeration declaredType="Mode" start="0"/></ScalarVariable>
    <ScalarVariable name="label" valueReference="7" causality="output" variability="discrete"
      initial="calculated"><String/></ScalarVariable>
    <ScalarVariable name="g" valueReference="8" causality="local" variability="constant">
      <Real start="9.81"/></ScalarVariable>
    <ScalarVariable name="k2" valueReference="9" causality="calculatedParameter"
      variability="fixed" initial="calculated"><Real/></ScalarVariable>
    <ScalarVariable name="txt" valueReference="10" causality="input" variability="discrete">
      <String start=""/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2" dependencies="1"/><Unknown index="8"/></Outputs>
    <InitialUnknowns><Unknown index="2" dependencies="1"/><Unknown index="8"/>
      <Unknown index="10"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""

FMI3_TYPED = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="tingen"
  instantiationToken="{a3e5c7d9-1b2f-4c6e-8a0d-2f4b6d8e0a1c}">
  <CoSimulation modelIdentifier="tingen" canHandleVariableCommunicationStepSize="true"/>
  <TypeDefinitions>
    <EnumerationType name="Mode">
      <Item name="off" value="0"/><Item name="on" value="1"/>
    </EnumerationType>
  </TypeDefinitions>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="F" valueReference="1" causality="input" variability="continuous" start="0"/>
    <Float64 name="theta" valueReference="2" causality="output" variability="continuous"/>
    <UInt8 name="u8" valueReference="3" causality="parameter" variability="fixed" start="1"/>
    <UInt32 name="u32" valueReference="4" causality="parameter" variability="tunable"
      start="1"/>
    <Int8 name="i8" valueReference="5" causality="parameter" variability="fixed" start="0"
      min="-10" max="10"/>
    <Int64 name="i64" valueReference="6" causality="parameter" variability="fixed" start="0"/>
    <Float32 name="f32" valueReference="7" causality="parameter" variability="fixed"
      start="0"/>
    <Enumeration name="mode" valueReference="8" declaredType="Mode" causality="parameter"
      variability="fixed" start="0"/>
    <Binary name="blob" valueReference="9" causality="parameter" variability="fixed">
      <Start value="00"/></Binary>
    <String name="note" valueReference="10" causality="output" variability="discrete"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="2"/><Output valueReference="10"/>
    <InitialUnknown valueReference="2"/><InitialUnknown valueReference="10"/>
  </ModelStructure>
</fmiModelDescription>
"""


def typed(built: Path, xml: str, out: Path) -> Path:
    """`built` with its modelDescription.xml replaced by `xml` (its binary kept)."""
    with zipfile.ZipFile(built) as src, zipfile.ZipFile(out, "w") as dst:
        for item in src.infolist():
            if item.filename != "modelDescription.xml":
                dst.writestr(item, src.read(item))
        dst.writestr("modelDescription.xml", xml)
    return out


def refused(server: Server, slug: str, body: dict[str, Any]) -> str:
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors", json=body)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"].startswith("application/problem+json")
    return str(r.json()["detail"])


def fmu(params: dict[str, Any], name: str = "p", **spec: Any) -> dict[str, Any]:
    return {"name": name, "blueprint": "fmu", "params": params, **spec}


@pytest.fixture(scope="module")
def twin2(server: Server, fmu_files: FmuFiles, tmp_path_factory: pytest.TempPathFactory) -> str:
    slug, _ = device_twin(server)
    upload(server, slug, fmu_files("status"))
    out = tmp_path_factory.mktemp("typed") / "typed2.fmu"
    upload(server, slug, typed(fmu_files("status"), FMI2_TYPED, out))
    return slug


@pytest.fixture(scope="module")
def twin3(server: Server, fmu_files: FmuFiles, tmp_path_factory: pytest.TempPathFactory) -> str:
    slug, _ = device_twin(server)
    out = tmp_path_factory.mktemp("typed") / "typed3.fmu"
    upload(server, slug, typed(fmu_files("tingen3"), FMI3_TYPED, out))
    return slug


@pytest.mark.parametrize(
    ("body", "words"),
    [
        (fmu({"fmu": "status.fmu", "outputs": ["z"]}), ["params.outputs", "no variable z"]),
        (fmu({"fmu": "missing.fmu"}), ["params.fmu", "no FMU 'missing.fmu'", "upload it"]),
        (fmu({"fmu": "status.fmu", "inputs": ["y"]}), ["params.inputs", "y", "not an input"]),
        (fmu({"fmu": "status.fmu"}, inputs={"uu": "x"}), ["inputs: uu", "it streams: u"]),
        (fmu({"fmu": "status.fmu", "parameters": {"y": 1.0}}), ["y", "calculated by the FMU"]),
        (fmu({"fmu": "typed2.fmu", "outputs": ["label"]}), ["label", "type String"]),
        (fmu({"fmu": "typed2.fmu", "inputs": ["txt"]}), ["txt", "type String"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"g": 1.0}}), ["g", "constant"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"k2": 1.0}}), ["k2", "calculatedParameter"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"count": 11}}), ["count", "range [0, 10]"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"count": 1.5}}), ["count", "whole number"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"big": 2**31}}), ["big", "range of Integer"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"on": 1}}), ["on", "true or false"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"mode": 2}}), ["mode", "fast (5)"]),
        (fmu({"fmu": "typed2.fmu", "parameters": {"mode": "medium"}}), ["mode", "not an item"]),
    ],
)
def test_fmi2_processors_the_fmu_cannot_run_are_refused(
    server: Server, twin2: str, body: dict[str, Any], words: list[str]
) -> None:
    detail = refused(server, twin2, body)
    assert all(w in detail for w in words), detail


@pytest.mark.parametrize(
    ("parameters", "words"),
    [
        ({"u8": 300}, ["u8", "300 is outside the range of UInt8 [0, 255]"]),
        ({"u32": -1}, ["u32", "-1 is outside the range of UInt32"]),
        ({"i8": 11}, ["i8", "declared range [-10, 10]"]),
        ({"i64": 2**63}, ["i64", "does not fit in 64 bits"]),  # refused by the API itself
        ({"f32": 1e39}, ["f32", "range of Float32"]),
        ({"mode": "dim"}, ["mode", "off (0), on (1)"]),
        ({"blob": "00"}, ["blob", "Binary cannot be set"]),
        ({"time": 1.0}, ["time", "independent"]),
    ],
)
def test_fmi3_typed_values_out_of_range_are_refused(
    server: Server, twin3: str, parameters: dict[str, Any], words: list[str]
) -> None:
    detail = refused(server, twin3, fmu({"fmu": "typed3.fmu", "parameters": parameters}))
    assert all(w in detail for w in words), detail


def test_fmi3_string_output_is_refused(server: Server, twin3: str) -> None:
    detail = refused(server, twin3, fmu({"fmu": "typed3.fmu", "outputs": ["theta", "note"]}))
    assert "note" in detail and "type String" in detail


def test_values_that_fit_are_kept_and_enumeration_names_stored_as_values(
    server: Server, twin2: str, twin3: str
) -> None:
    values = {"u8": 255, "u32": 4294967295, "i8": -10, "i64": -(2**63), "mode": "on"}
    made = create(server, twin3, **fmu({"fmu": "typed3.fmu", "parameters": values}, enabled=False))
    assert made["params"]["parameters"] == {**values, "mode": 1}
    made = create(
        server, twin2,
        **fmu({"fmu": "typed2.fmu", "inputs": ["u"], "outputs": ["y"],
               "parameters": {"count": 10, "on": True, "mode": "fast", "u": 2.0}},
              name="ok", inputs={"u": "x"}, enabled=False),
    )  # fmt: skip
    assert made["params"]["parameters"] == {"count": 10, "on": True, "mode": 5, "u": 2.0}


def test_an_update_is_checked_as_a_create(server: Server, twin2: str) -> None:
    create(server, twin2, **fmu({"fmu": "status.fmu"}, name="upd", enabled=False))
    path = f"/api/v1/twins/{twin2}/processors/upd"
    with server.admin as admin:
        r = admin.patch(path, json={"params": {"fmu": "status.fmu", "outputs": ["nope"]}})
        assert r.status_code == 422 and "no variable nope" in r.text, r.text
        r = admin.patch(path, json={"inputs": {"U": "x"}})
        assert r.status_code == 422 and "inputs: U" in r.text, r.text
        r = admin.patch(path, json={"params": {"fmu": "gone.fmu"}})
        assert r.status_code == 422 and "no FMU 'gone.fmu'" in r.text, r.text
    assert processor(server, twin2, "upd")["params"] == {"fmu": "status.fmu"}


def test_a_library_fmu_is_checked_by_the_same_rules_at_create_and_update(
    server: Server, fmu_files: FmuFiles, tmp_path: Path
) -> None:
    name = unique("typed")
    push_fmu(server, name, typed(fmu_files("tingen3"), FMI3_TYPED, tmp_path / "typed3.fmu"))
    slug, _ = device_twin(server)
    ref = f"lib:models/{name}"
    detail = refused(server, slug, fmu({"fmu": ref, "parameters": {"u8": 300}}))
    assert "u8" in detail and "range of UInt8" in detail
    detail = refused(server, slug, fmu({"fmu": ref}, inputs={"f": "x"}))
    assert "inputs: f" in detail and "it streams: F" in detail
    made = create(server, slug, **fmu({"fmu": ref, "parameters": {"mode": "on"}}, enabled=False))
    assert made["params"]["parameters"] == {"mode": 1}
    pinned = made["params"]["fmu"]
    path = f"/api/v1/twins/{slug}/processors/p"
    with server.admin as admin:  # the pinned version's description, the FMU unchanged
        r = admin.patch(path, json={"params": {"fmu": pinned, "parameters": {"u32": -1}}})
        assert r.status_code == 422 and "u32" in r.text and "UInt32" in r.text, r.text
        r = admin.patch(path, json={"params": {"fmu": pinned, "outputs": ["note"]}})
        assert r.status_code == 422 and "type String" in r.text, r.text
        r = admin.patch(path, json={"params": {"fmu": pinned, "parameters": {"u32": 7}}})
        assert r.status_code == 200, r.text
