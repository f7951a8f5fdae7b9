"""`twinlink apply -f DIR` applies the DT documents under DIR, not the library assets there."""

from __future__ import annotations

from pathlib import Path

from twinlink.cli.apply import _document_files


def test_a_folder_walk_leaves_library_assets_out(tmp_path: Path) -> None:
    (tmp_path / "twin-a.yaml").write_text("name: a\n")
    package = tmp_path / "library" / "rig"
    package.mkdir(parents=True)
    (package / "twin.yaml").write_text("document: document.yaml\n")
    (package / "document.yaml").write_text("name: ${deployment.name}\n")
    dtaas = tmp_path / "library" / "msd"
    (dtaas / "lifecycle").mkdir(parents=True)
    (dtaas / "config.json").write_text("{}")
    tool = tmp_path / "library" / "sim"
    tool.mkdir()
    (tool / "asset.yaml").write_text("description: a tool\n")
    (tmp_path / "library" / "hall.yml").write_text("name: hall\n")

    found = _document_files((str(tmp_path),))

    assert found == [tmp_path / "library" / "hall.yml", tmp_path / "twin-a.yaml"]


def test_a_file_named_is_applied_whatever_folder_it_is_in(tmp_path: Path) -> None:
    package = tmp_path / "rig"
    package.mkdir()
    (package / "twin.yaml").write_text("document: document.yaml\n")
    named = package / "document.yaml"
    named.write_text("name: x\n")
    assert _document_files((str(named),)) == [named]
