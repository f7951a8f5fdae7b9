"""`twinlink export` and `twinlink import wot-td|dtdl|aas`, the real command run as a
subprocess against a real server: exports written whole and valid, imports that read an export
back into the same interface, and an import merged into another twin through the API."""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import pytest
import yaml
from basyx.aas import model
from basyx.aas.adapter.aasx import AASXReader, DictSupplementaryFileContainer

from tests.conftest import EXAMPLES, Server
from tests.integration._util import apply, get_doc, twin_doc, unique
from tests.integration.test_cli import Cli
from twinlink.formats.aas import validate_aas
from twinlink.formats.dtdl import validate_dtdl
from twinlink.formats.wot import validate_wot

pytestmark = pytest.mark.integration

TINGEN = EXAMPLES / "tingen" / "tingen.yaml"
# `twinlink export --format` and `twinlink import` of each exchange format
IMPORTS = {"wot-td": "wot-td", "dtdl": "dtdl", "aas-json": "aas"}
LISTS = ("signals", "properties", "commands")


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


@pytest.fixture(scope="module")
def tingen(cli: Cli) -> str:
    cli("apply", "-f", str(TINGEN)).ok()
    return "tingen"


def _names(interface: dict[str, Any]) -> dict[str, list[str]]:
    return {kind: [e["name"] for e in interface.get(kind) or []] for kind in LISTS}


def test_export_prints_the_document_as_yaml_and_json(cli: Cli, server: Server, tingen: str) -> None:
    as_yaml, as_json = cli.many(["export", tingen], ["export", tingen, "--format", "json"])
    with server.admin as admin:
        doc = get_doc(admin, tingen)
    assert yaml.safe_load(as_yaml.ok().out) == doc
    assert json.loads(as_json.ok().out) == doc


@pytest.mark.parametrize(
    ("fmt", "validate"),
    [("wot-td", validate_wot), ("dtdl", validate_dtdl), ("aas-json", validate_aas)],
)
def test_export_writes_a_valid_file(
    cli: Cli, tingen: str, tmp_path: Path, fmt: str, validate: Any
) -> None:
    target = tmp_path / f"tingen.{fmt}.json"
    result = cli("export", tingen, "-f", fmt, "-o", str(target)).ok()
    assert f"to {target}" in result.err
    assert validate(json.loads(target.read_bytes())) == []
    assert not target.with_name(target.name + ".part").exists()


def test_export_writes_an_aasx_package_basyx_reads(cli: Cli, tingen: str, tmp_path: Path) -> None:
    target = tmp_path / "tingen.aasx"
    cli("export", tingen, "--format", "aasx", "-o", str(target)).ok()
    objects: model.DictIdentifiableStore = model.DictIdentifiableStore()  # type: ignore[type-arg]
    with AASXReader(io.BytesIO(target.read_bytes())) as reader:
        files = DictSupplementaryFileContainer()  # type: ignore[no-untyped-call]
        reader.read_into(objects, files)
    assert any(isinstance(o, model.AssetAdministrationShell) for o in objects)


def test_export_of_a_twin_the_caller_may_not_see_fails_plainly(
    cli: Cli, server: Server, tmp_path: Path
) -> None:
    slug = unique("hidden")
    with server.admin as admin:
        apply(admin, twin_doc(f"https://twins.example/{slug}", privacy="private"))
    target = tmp_path / "hidden.td.json"
    result = cli("export", slug, "-f", "wot-td", "-o", str(target), token=False)
    assert result.code == 1
    assert "(404)" in result.err and "Traceback" not in result.err
    assert not target.exists()
    cli("export", slug, "-f", "wot-td", "-o", str(target)).ok()
    assert target.exists()


@pytest.mark.parametrize("fmt", sorted(IMPORTS))
def test_an_export_imports_back_into_the_same_interface(
    cli: Cli, tingen: str, tmp_path: Path, fmt: str
) -> None:
    exported = tmp_path / f"tingen.{fmt}.json"
    cli("export", tingen, "-f", fmt, "-o", str(exported)).ok()
    result = cli("import", IMPORTS[fmt], str(exported)).ok()
    document = yaml.safe_load(result.out)
    original = yaml.safe_load(TINGEN.read_text("utf-8"))
    assert document["version"] == "1.0"
    assert document["name"] == original["name"]
    assert _names(document["interface"]) == _names(original["interface"])


def test_an_aasx_package_imports_as_its_json_does(cli: Cli, tingen: str, tmp_path: Path) -> None:
    package, environment = tmp_path / "tingen.aasx", tmp_path / "tingen.aas.json"
    cli.many(
        ["export", tingen, "-f", "aasx", "-o", str(package)],
        ["export", tingen, "-f", "aas-json", "-o", str(environment)],
    )
    from_package, from_json = cli.many(
        ["import", "aas", str(package)], ["import", "aas", str(environment)]
    )
    document = yaml.safe_load(from_package.ok().out)
    assert document == yaml.safe_load(from_json.ok().out)
    original = yaml.safe_load(TINGEN.read_text("utf-8"))
    assert _names(document["interface"]) == _names(original["interface"])
    broken = tmp_path / "broken.aasx"
    broken.write_bytes(package.read_bytes()[: len(package.read_bytes()) // 2])
    result = cli("import", "aas", str(broken))
    assert result.code == 1 and "not an AASX package" in result.err
    assert "Traceback" not in result.err


def test_an_import_merges_into_a_twin_with_a_dry_run_first(
    cli: Cli, server: Server, tingen: str, tmp_path: Path
) -> None:
    slug = unique("pump")
    own = {"signals": [{"name": "Flow_m3ps", "unit": "m3/s"}], "commands": [{"name": "pause"}]}
    with server.admin as admin:
        apply(admin, twin_doc(f"https://twins.example/{slug}", name="Pump", interface=own))
        before = get_doc(admin, slug)
    exported = tmp_path / "tingen.dtdl.json"
    cli("export", tingen, "-f", "dtdl", "-o", str(exported)).ok()

    dry = cli("import", "dtdl", str(exported), "--twin", slug).ok()
    assert "dry run" in dry.out and "would be updated" in dry.out
    with server.admin as admin:
        assert get_doc(admin, slug) == before

    done = cli("import", "dtdl", str(exported), "--twin", slug, "--apply").ok()
    assert f"twin/{slug} part public: updated" in done.out
    with server.admin as admin:
        after = get_doc(admin, slug)
    tingen_names = _names(yaml.safe_load(TINGEN.read_text("utf-8"))["interface"])
    names = _names(after["interface"])
    # The pump's own signal stays; tingen's `pause` takes the place of the pump's; the rest
    # is added after them.
    assert names["signals"] == ["Flow_m3ps", *tingen_names["signals"]]
    assert names["commands"] == ["pause", *(c for c in tingen_names["commands"] if c != "pause")]
    assert names["properties"] == tingen_names["properties"]
    assert after["name"] == "Pump"  # only the interface is merged
    # tingen's default_device names a device of tingen, not of the pump
    assert "default_device" not in after["interface"]
    again = cli("import", "dtdl", str(exported), "--twin", slug, "--apply").ok()
    assert f"twin/{slug} part public: unchanged" in again.out


def test_an_invalid_file_is_refused_with_its_problems(cli: Cli, tmp_path: Path) -> None:
    bad = tmp_path / "bad.td.json"
    bad.write_text(json.dumps({"title": 5, "properties": []}))
    result = cli("import", "wot-td", str(bad))
    assert result.code == 1
    assert "is not a valid wot-td document" in result.err and "Traceback" not in result.err
    not_json = tmp_path / "not.json"
    not_json.write_text("title: yaml")
    result = cli("import", "dtdl", str(not_json))
    assert result.code == 1 and "is not JSON" in result.err


def test_apply_without_a_twin_is_a_usage_error(cli: Cli, tmp_path: Path) -> None:
    source = tmp_path / "td.json"
    source.write_text("{}")
    result = cli("import", "wot-td", str(source), "--apply")
    assert result.code == 2
    assert "--apply and --part need --twin SLUG" in result.err
