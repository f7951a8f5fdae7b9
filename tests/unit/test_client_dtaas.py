"""`twinlink lib import-dtaas`'s reading of a DTaaS digital twin folder and the twin.yaml it
generates (a package the deploy side accepts), and `twinlink deploy`'s parameters and plans."""

from __future__ import annotations

from pathlib import Path

import click
import pytest
import yaml

from tests.conftest import EXAMPLES
from twinlink.cli.deploy import parse_parameters, print_plan
from twinlink.cli.dtaas import read_dtaas, twin_yaml
from twinlink.deploy.package import parse_package


def dtaas_folder(root: Path) -> Path:
    """A DTaaS-style twin, laid out as DTaaS's mass-spring-damper is: description, README,
    two co-simulation config files, lifecycle scripts (create not executable, as in many
    DTaaS repositories), and a picture for the README."""
    (root / "lifecycle").mkdir(parents=True)
    (root / "description.md").write_text(
        "# Mass Spring Damper\n\nTwo mass spring dampers\ncoupled in a co-simulation ${x}.\n\n"
        "More text.\n"
    )
    (root / "README.md").write_text("# Mass Spring Damper\n\nRun lifecycle/execute.\n")
    (root / "cosim.json").write_text('{"fmus": {}, "connections": {}}\n')
    (root / "time.json").write_text('{"startTime": 0.0, "endTime": 10.0}\n')
    (root / "structure.png").write_bytes(b"\x89PNG")
    (root / ".gitlab-ci.yml").write_text("stages: [execute]\n")
    for phase, text in {
        "create": "echo create",
        "execute": "echo run",
        "clean": "rm -f out",
    }.items():
        script = root / "lifecycle" / phase
        script.write_text(f"#!/bin/bash\n{text}\n")
        script.chmod(0o644 if phase == "create" else 0o755)
    return root


def test_a_dtaas_folder_is_read_whole(tmp_path: Path) -> None:
    twin = read_dtaas(dtaas_folder(tmp_path / "Mass_Spring_Damper"))
    assert twin.name == "mass_spring_damper"
    assert twin.phases == ["create", "execute", "clean"]
    assert twin.description == "Two mass spring dampers coupled in a co-simulation ${x}."
    assert [p for p, _ in twin.config] == ["cosim.json", "time.json"]
    assert [p for p, _ in twin.files] == [
        ".gitlab-ci.yml", "README.md", "cosim.json", "description.md",
        "lifecycle/clean", "lifecycle/create", "lifecycle/execute", "structure.png", "time.json",
    ]  # fmt: skip


def test_the_generated_twin_yaml_is_a_package_the_deploy_side_takes(tmp_path: Path) -> None:
    twin = read_dtaas(dtaas_folder(tmp_path / "msd"), name="msd")
    ref = "lib:user:ada/data/msd-config@sha256:" + "a" * 64
    text = twin_yaml(twin, ref)
    package = parse_package(text)
    assert package.assets == {"config": ref}
    assert package.description == twin.description
    assert isinstance(package.document, dict)
    assert package.document["name"] == "${deployment.name}"
    assert package.document["description"].endswith("co-simulation $${x}.")  # a literal ${
    assert "create, execute, clean" in package.document["features"][0]["description"]
    assert "assets" not in yaml.safe_load(twin_yaml(twin, None))


def test_the_shipped_dtaas_example_imports(tmp_path: Path) -> None:
    twin = read_dtaas(EXAMPLES / "library" / "mass-spring-damper")
    assert twin.name == "mass-spring-damper"
    assert {"create", "execute", "analyze"} <= set(twin.phases)
    assert [p for p, _ in twin.config] == ["config.json"]
    parse_package(twin_yaml(twin, None))


@pytest.mark.parametrize(
    ("make", "says"),
    [
        (lambda p: p.mkdir(), "has no lifecycle/ scripts"),
        (lambda p: (p.mkdir(), (p / "twin.yaml").write_text("{}")), "a twin package already"),
        (lambda p: p.write_text("x"), "is not a folder"),
    ],
)
def test_what_is_not_a_dtaas_twin_is_refused(tmp_path: Path, make: object, says: str) -> None:
    folder = tmp_path / "x"
    make(folder)  # type: ignore[operator]
    with pytest.raises(ValueError, match=says):
        read_dtaas(folder)


def test_a_folder_name_is_made_an_asset_name_or_name_is_asked_for(tmp_path: Path) -> None:
    assert read_dtaas(dtaas_folder(tmp_path / "Ünï Twin")).name == "n-twin"
    with pytest.raises(ValueError, match="give --name"):
        read_dtaas(dtaas_folder(tmp_path / "ÅÄÖ"))
    with pytest.raises(ValueError, match="give --name"):
        read_dtaas(dtaas_folder(tmp_path / "ok"), name="Bad Name")


def test_parameters_are_yaml_scalars() -> None:
    pairs = ("zeta=0.7", "n=3", "on=true", "label=beam 1", "v=1.0.0", "e=", "xs=[1, 2]", "bad=[1",
             "mode=on", "off=False")  # fmt: skip
    assert parse_parameters(pairs) == {
        "zeta": 0.7,
        "n": 3,
        "on": True,
        "label": "beam 1",
        "v": "1.0.0",
        "e": "",
        "xs": [1, 2],
        "bad": "[1",
        "mode": "on",
        "off": False,
    }
    with pytest.raises(click.BadParameter, match="is not key=value"):
        parse_parameters(("zeta",))


def test_a_plan_prints_as_terraform_does(capsys: pytest.CaptureFixture[str]) -> None:
    print_plan({
        "create": [{"type": "twin", "name": "rig", "spec": {}},
                   {"type": "device", "name": "sim", "spec": {}}],
        "update": [{"type": "processor", "name": "fmu",
                    "changes": [{"path": "params.zeta", "from": 0.7, "to": 0.9}]}],
        "delete": [{"type": "connector", "name": "udp"}],
        "keep": [{"type": "service", "name": "cad"}],
    })  # fmt: skip
    assert capsys.readouterr().out.splitlines() == [
        "+ twin       rig",
        "+ device     sim",
        "~ processor  fmu",
        "      params.zeta: 0.7 -> 0.9",
        "- connector  udp",
        "Plan: 2 to create, 1 to update, 1 to delete, 1 unchanged.",
    ]
