"""inspect_fmu: describing good FMUs, refusing bad files with a clear FmuError."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import pytest

from tests.integration._fmu_c import FMI2_XML, build_fmu
from twinlink.processors.fmuinfo import FmuError, check_archive, inspect_fmu

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def fmus(tmp_path_factory: pytest.TempPathFactory) -> dict[int, Path]:
    folder = tmp_path_factory.mktemp("fmus")
    return {v: build_fmu(folder, v, f"lag{v}.fmu") for v in (2, 3)}


def _zip(path: Path, entries: dict[str, str | bytes]) -> Path:
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in entries.items():
            zf.writestr(name, data)
    return path


def test_fmi2_description(fmus: dict[int, Path]) -> None:
    info = inspect_fmu(fmus[2])
    assert (info.fmi_version, info.model_name, info.guid) == ("2.0", "lag", "{GUID}")
    assert info.description == "first-order lag"
    assert info.generation_tool == "twinlink tests"
    assert info.co_simulation and info.model_exchange and info.has_binary
    assert info.platform == "linux64"
    assert info.default_experiment.step == 0.01 and info.default_experiment.stop == 10.0
    assert info.number_of_continuous_states == 1 and info.number_of_event_indicators == 1
    u = info.variable("u")
    assert u is not None
    assert (u.causality, u.variability, u.type, u.unit) == ("input", "continuous", "Real", "m")
    assert (u.start, u.min, u.max, u.value_reference) == (0.0, -10.0, 10.0, 1)
    assert u.description == "input"
    tau = info.variable("tau")
    assert tau is not None
    assert (tau.causality, tau.variability, tau.start, tau.unit) == (
        "parameter",
        "tunable",
        1.0,
        "s",
    )
    n, label = info.variable("n"), info.variable("label")
    assert n is not None and label is not None
    assert (n.type, label.type, label.start) == ("Integer", "String", "lag")
    d = info.as_dict()
    json.dumps(d, allow_nan=False)  # JSON-ready
    assert [v["name"] for v in d["variables"]] == ["u", "y", "der(y)", "g", "tau", "n", "label"]
    assert d["interfaces"][1]["needs_completed_integrator_step"] is True


def test_fmi3_description(fmus: dict[int, Path]) -> None:
    info = inspect_fmu(fmus[3])
    assert (info.fmi_version, info.guid, info.platform) == ("3.0", "{GUID}", "x86_64-linux")
    types = {v.name: v.type for v in info.variables}
    assert types == {
        "time": "Float64",
        "u": "Float64",
        "y": "Float64",
        "der(y)": "Float64",
        "g": "Float64",
        "tau": "Float64",
        "n": "Int32",
        "label": "String",
        "z": "Float64",
    }
    u = info.variable("u")
    assert u is not None and (u.min, u.max, u.causality) == (-10.0, 10.0, "input")
    json.dumps(info.as_dict(), allow_nan=False)


def test_garbage_bytes(tmp_path: Path) -> None:
    path = tmp_path / "x.fmu"
    path.write_bytes(b"\x00garbage" * 100)
    with pytest.raises(FmuError, match="not a ZIP archive"):
        inspect_fmu(path)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FmuError, match="no FMU file"):
        inspect_fmu(tmp_path / "nope.fmu")


def test_no_model_description(tmp_path: Path) -> None:
    path = _zip(tmp_path / "x.fmu", {"binaries/linux64/lag.so": b"x"})
    with pytest.raises(FmuError, match=r"no modelDescription\.xml"):
        inspect_fmu(path)


@pytest.mark.parametrize("entry", ["../evil.so", "binaries/../../evil.so", "/etc/evil", "a\\b"])
def test_zip_slip_refused(tmp_path: Path, entry: str) -> None:
    path = _zip(tmp_path / "x.fmu", {"modelDescription.xml": FMI2_XML, entry: b"x"})
    with pytest.raises(FmuError, match="is not allowed"):
        inspect_fmu(path)


def test_too_large_refused(fmus: dict[int, Path]) -> None:
    with pytest.raises(FmuError, match="unpacks to"):
        inspect_fmu(fmus[2], max_unpacked=1000)
    assert "modelDescription.xml" in check_archive(fmus[2], 10**6)


def test_invalid_model_description(tmp_path: Path) -> None:
    bad = FMI2_XML.replace('causality="input"', 'causality="sideways"')
    path = _zip(tmp_path / "x.fmu", {"modelDescription.xml": bad})
    with pytest.raises(FmuError, match="is not a valid FMU") as err:
        inspect_fmu(path)
    assert "sideways" in str(err.value)
    assert "\n- " in str(err.value)  # problems are listed


@pytest.mark.parametrize(
    ("xml", "message"),
    [
        (
            "<fmiModelDescription",
            "cannot read modelDescription.xml: Couldn't find end of Start Tag",
        ),
        ("<fmiModelDescription/>", "has no fmiVersion"),
        ('<fmiModelDescription fmiVersion="1.0"/>', "FMI 1.0 FMU; only FMI 2.0 and 3.0"),
    ],
)
def test_unreadable_model_description(tmp_path: Path, xml: str, message: str) -> None:
    path = _zip(tmp_path / "x.fmu", {"modelDescription.xml": xml})
    with pytest.raises(FmuError, match=message):
        inspect_fmu(path)


def test_no_binary_for_this_platform(tmp_path: Path) -> None:
    entries: dict[str, str | bytes] = {"modelDescription.xml": FMI2_XML}
    entries["binaries/win64/lag.dll"] = b"MZ"
    path = _zip(tmp_path / "x.fmu", entries)
    with pytest.raises(FmuError, match=r"no binary for this platform \(linux64\).*win64"):
        inspect_fmu(path)
    info = inspect_fmu(path, require_binary=False)
    assert not info.has_binary and info.co_simulation
