"""read_system: the reader chosen by extension or content, a multi-model with its coe.json
found either way, and Maestro's stabilisation named as not applied."""

from __future__ import annotations

import json
import logging
import shutil
from pathlib import Path

import pytest

from tests.unit.test_cosim_formats import MSD, assert_msd, make_ssp
from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import CosimFormatError
from twinlink.cosim.reading import format_of, read_system, unapplied
from twinlink.cosim.yamlform import read_yaml


def test_each_extension_reads_with_its_reader(tmp_path: Path) -> None:
    for path in (MSD / "maestro2.json", MSD / "msd.yaml", make_ssp(tmp_path / "msd.ssp")):
        assert_msd(read_system(path, step_size=0.01))
    assert read_system(MSD / "maestro2.json") == read_maestro(MSD / "maestro2.json")
    yml = tmp_path / "msd.yml"
    shutil.copy(MSD / "msd.yaml", yml)
    assert read_system(yml) == read_yaml(yml)


def test_without_a_known_extension_the_content_tells(tmp_path: Path) -> None:
    ssp, maestro, yaml = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    make_ssp(ssp)
    shutil.copy(MSD / "maestro2.json", maestro)
    shutil.copy(MSD / "msd.yaml", yaml)
    assert [format_of(p) for p in (ssp, maestro, yaml)] == ["ssp", "maestro", "yaml"]
    assert read_system(maestro).source == "maestro" and read_system(yaml).source == "yaml"
    plain_zip = tmp_path / "d"
    shutil.make_archive(str(plain_zip), "zip", MSD)
    with pytest.raises(CosimFormatError, match=r"d\.zip: a zip archive without SystemStructure"):
        format_of(plain_zip.with_suffix(".zip").rename(tmp_path / "d.zip"))


def test_a_multimodel_takes_the_coe_json_beside_it() -> None:
    """tests/cosim_files/msd/mm.json has no algorithm; its coe.json has a 1 ms fixed step."""
    system = read_system(MSD / "mm.json")
    assert system == read_maestro(MSD / "mm.json", settings="coe.json")
    assert system.algorithm.kind == "fixed-step" and system.algorithm.size == 0.001


def intocps_project(tmp_path: Path) -> Path:
    """The INTO-CPS app's layout: the settings in a folder below the multi-model's, naming it
    relative to the project."""
    model_dir = tmp_path / "project" / "Multi-models" / "msd"
    (model_dir / "co-sim-1").mkdir(parents=True)
    shutil.copy(MSD / "mm.json", model_dir / "mm.json")
    coe = model_dir / "co-sim-1" / "coe.json"
    shutil.copy(MSD / "coe.json", coe)
    return coe


def test_a_coe_json_finds_its_multimodel_inside_root(tmp_path: Path) -> None:
    coe = intocps_project(tmp_path)
    system = read_system(coe, root=tmp_path / "project")
    assert system == read_maestro(coe.parents[1] / "mm.json", settings=coe)
    # by its name alone, in the folder above, once root lets it be read
    assert read_system(coe, root=coe.parents[1]) == system
    with pytest.raises(CosimFormatError, match="is not found from this folder"):
        read_system(coe)


def test_a_coe_json_reads_nothing_outside_root(tmp_path: Path) -> None:
    coe = intocps_project(tmp_path)
    shutil.move(coe.parents[1] / "mm.json", tmp_path / "project" / "elsewhere.json")
    settings = json.loads(coe.read_text()) | {"multimodel_path": "elsewhere.json"}
    coe.write_text(json.dumps(settings))
    with pytest.raises(CosimFormatError, match=r"'elsewhere\.json' is not found"):
        read_system(coe)
    assert read_system(coe, root=tmp_path / "project").source == "maestro"
    coe.write_text(json.dumps(settings | {"multimodel_path": "../../../elsewhere.json"}))
    with pytest.raises(CosimFormatError, match="leaves the folder"):
        read_system(coe, root=tmp_path)


def test_a_json_that_is_neither_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "x.json"
    path.write_text('{"startTime": 0}')
    with pytest.raises(CosimFormatError, match=r'x.json: neither a multi-model \(no "fmus"\)'):
        read_system(path)
    path.write_text("[1, 2]")
    with pytest.raises(CosimFormatError, match=r"x\.json: is not a JSON object"):
        read_system(path)
    path.write_text("{\n  nope")
    with pytest.raises(CosimFormatError, match=r"x\.json: line 2, column 3"):
        read_system(path)


def test_var_step_constraints_are_read_and_stabilisation_named_as_not_applied(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """Maestro's own var-step test file's settings with the multi-model, in one file: its
    constraint is read (and applied by the master, no warning); stabilisation is not done."""
    model = json.loads((MSD / "mm.json").read_text())
    settings = json.loads((MSD / "varstep.json").read_text())
    path = tmp_path / "varstep.json"
    path.write_text(json.dumps(model | settings))
    with caplog.at_level(logging.WARNING, logger="twinlink.cosim"):
        system = read_system(path)
    assert system.algorithm.kind == "var-step"
    assert [c.kind for c in system.algorithm.constraints] == ["boundeddifference"]
    assert unapplied(path) == [] and caplog.messages == []
    path.write_text(
        json.dumps(
            model
            | settings
            | {
                "stabalizationEnabled": True,
                "global_absolute_tolerance": 0.0,
                "global_relative_tolerance": 0.01,
            }
        )
    )
    with caplog.at_level(logging.WARNING, logger="twinlink.cosim"):
        read_system(path)
    notes = unapplied(path)
    assert notes == [
        "stabalizationEnabled is not applied: the masters step each FMU once per step and do "
        "not iterate until the coupled values settle (its global_absolute_tolerance 0.0, "
        "global_relative_tolerance 0.01 are not used)"
    ]
    assert caplog.messages == [f"varstep.json: {notes[0]}"]
    assert unapplied(MSD / "maestro2.json") == [] and unapplied(MSD / "msd.yaml") == []
