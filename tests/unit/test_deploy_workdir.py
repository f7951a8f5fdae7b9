"""A deployment's working folder (deploy/workdir.py): filled once with copies of its package
version, a new version's files put over the old's (the old's others removed), the scripts'
files kept, removed whole."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from twinlink.deploy import workdir


def version(files: dict[str, str], blobs: Path) -> workdir.Materialize:
    """A package version as the library materializes it: hard links to read-only blobs."""

    async def materialize(dest: Path) -> None:
        for path, text in files.items():
            blob = blobs / f"{abs(hash(text))}"
            if not blob.exists():
                blob.parent.mkdir(parents=True, exist_ok=True)
                blob.write_text(text)
                blob.chmod(0o444)
            (dest / path).parent.mkdir(parents=True, exist_ok=True)
            os.link(blob, dest / path)

    return materialize


async def test_a_folder_is_filled_once_with_copies(tmp_path: Path) -> None:
    work = workdir.folder(tmp_path / "deployments", 7)
    v1 = version({"twin.yaml": "a: 1\n", "lifecycle/execute": "echo\n"}, tmp_path / "blobs")
    assert await workdir.prepare(work, "v1", v1)
    assert work == tmp_path / "deployments" / "7" / "work"
    assert (work / "twin.yaml").read_text() == "a: 1\n"
    info = (work / "twin.yaml").stat()
    assert info.st_nlink == 1 and stat.S_IMODE(info.st_mode) == 0o444  # a copy, as read-only
    (work / "results.csv").write_text("made by execute\n")
    (work / "twin.yaml").chmod(0o644)
    (work / "twin.yaml").write_text("changed by a script\n")
    assert not await workdir.prepare(work, "v1", v1)  # the same version: left as it is
    assert (work / "twin.yaml").read_text() == "changed by a script\n"
    assert (work / "results.csv").exists()
    assert sorted(p.name for p in work.parent.iterdir()) == ["package.json", "work"]


async def test_a_new_version_replaces_the_packages_files_and_keeps_the_scripts(
    tmp_path: Path,
) -> None:
    work = workdir.folder(tmp_path, 1)
    blobs = tmp_path / "blobs"
    old = {"data.txt": "old\n", "old/only.txt": "x\n", "old/deep/too.txt": "y\n", "keep/a": "a\n"}
    await workdir.prepare(work, "v1", version(old, blobs))
    (work / "results").mkdir()
    (work / "results" / "out.txt").write_text("kept\n")
    (work / "keep" / "script-made").write_text("kept too\n")
    new = {"data.txt": "new\n", "keep/a": "a2\n", "new.txt": "n\n"}
    assert await workdir.prepare(work, "v2", version(new, blobs))
    assert (work / "data.txt").read_text() == "new\n"
    assert (work / "keep" / "a").read_text() == "a2\n"
    assert (work / "new.txt").exists()
    assert not (work / "old").exists()  # the old version's files and the folders they emptied
    assert (work / "results" / "out.txt").read_text() == "kept\n"
    assert (work / "keep" / "script-made").read_text() == "kept too\n"
    assert not (work.parent / "stage").exists()

    workdir.remove(tmp_path, 1)
    assert not (tmp_path / "1").exists()
    assert (blobs).is_dir() and all(b.read_text() for b in blobs.iterdir())  # blobs untouched
