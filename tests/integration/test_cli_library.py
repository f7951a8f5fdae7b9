"""`twinlink lib` run as a subprocess against a real server: push a folder and a file, list,
show, versions, pull (unpacked, one file, the archive), tag, rm, and mistakes said plainly."""

from __future__ import annotations

import os
import stat
import tarfile
from pathlib import Path

import pytest

from tests.conftest import Server
from tests.integration._util import unique
from tests.integration.test_cli import Cli

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


def _tool(root: Path) -> Path:
    (root / "bin").mkdir(parents=True)
    (root / "README.md").write_text("# a tool\n")
    script = root / "bin" / "run.sh"
    script.write_text("#!/bin/sh\necho ran\n")
    script.chmod(0o755)
    (root / "data.bin").write_bytes(os.urandom(3 << 20))  # several chunks
    return root


def test_push_a_folder_then_pull_it_back(cli: Cli, tmp_path: Path) -> None:
    name = unique("tool")
    src = _tool(tmp_path / "src")
    pushed = cli("lib", "push", str(src), "--kind", "tools", "--name", name, "--tag", "1.0.0",
                 "--description", "A tool for the tests").ok()  # fmt: skip
    assert pushed.out.startswith(f"pushed user:admin/tools/{name}@sha256:"), pushed.out
    assert "(3 files, 3.1 MB) tags: " in pushed.out and "1.0.0" in pushed.out
    again = cli("lib", "push", str(src), "--kind", "tools", "--name", name, "--tag", "stable").ok()
    assert again.out.startswith("unchanged (same content as)"), again.out

    listed = cli("lib", "ls", "--kind", "tools").ok().out
    [line] = [line for line in listed.splitlines() if name in line]
    assert "1.0.0,latest,stable" in line and "A tool for the tests" in line

    out = tmp_path / "out"
    cli("lib", "pull", f"tools/{name}@stable", "-o", str(out)).ok()
    for path in ("README.md", "bin/run.sh", "data.bin"):
        assert (out / path).read_bytes() == (src / path).read_bytes(), path
    assert os.stat(out / "bin" / "run.sh").st_mode & stat.S_IXUSR
    assert not os.stat(out / "README.md").st_mode & stat.S_IXUSR

    cli("lib", "pull", f"user:admin/tools/{name}#bin/run.sh", "-o", str(tmp_path / "one")).ok()
    assert (tmp_path / "one" / "run.sh").read_text() == "#!/bin/sh\necho ran\n"

    archive = tmp_path / "tool.tgz"
    cli("lib", "pull", f"tools/{name}@1.0.0", "--archive", str(archive)).ok()
    with tarfile.open(archive) as tar:
        assert sorted(tar.getnames()) == ["README.md", "bin/run.sh", "data.bin"]


def test_a_file_versions_tags_and_rm(cli: Cli, tmp_path: Path) -> None:
    name = unique("table")
    first, second = tmp_path / "v1.csv", tmp_path / "v2.csv"
    first.write_text("t,x\n0,1\n")
    second.write_text("t,x\n0,2\n")
    cli("lib", "push", str(first), "--kind", "data", "--name", name, "--tag", "1").ok()
    cli("lib", "push", str(second), "--kind", "data", "--name", name, "--tag", "2").ok()
    versions = cli("lib", "versions", f"data/{name}").ok().out.splitlines()
    assert versions[0].split()[:2] == ["VERSION", "TAGS"]
    assert [v.split()[1] for v in versions[1:]] == ["2,latest", "1"]  # newest first
    old = versions[2].split()[0]

    shown = cli("lib", "show", f"data/{name}@1").ok().out
    assert "path: v1.csv" in shown
    cli("lib", "tag", f"data/{name}@{old}", "latest").ok()
    cli("lib", "pull", f"data/{name}", "-o", str(tmp_path / "latest")).ok()
    assert (tmp_path / "latest" / "v1.csv").read_text() == "t,x\n0,1\n"

    cli("lib", "rm", f"data/{name}", "--version", "2").ok()
    assert len(cli("lib", "versions", f"data/{name}").ok().out.splitlines()) == 2
    assert f"deleted user:admin/data/{name}" in cli("lib", "rm", f"data/{name}").ok().out
    gone = cli("lib", "show", f"data/{name}")
    assert gone.code == 1 and "no asset data/" in gone.err and "Traceback" not in gone.err


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["lib", "pull", "tingen-beam"], "is not a library reference"),
        (["lib", "show", "fmus/beam"], "the kind 'fmus' is not one of"),
        (["lib", "push", "README.md", "--kind", "data", "--name", "Bad Name"], "(422)"),
        (
            ["lib", "push", "README.md", "--kind", "data", "--name", "x", "--scope", "common"],
            "",
        ),  # admins write common: accepted
    ],
)
def test_mistakes_are_said_plainly(cli: Cli, args: list[str], says: str) -> None:
    result = cli(*args)
    assert "Traceback" not in result.err
    if says:
        assert result.code != 0 and says in result.err, result.err
    else:
        result.ok()


def test_a_link_in_a_pushed_folder_is_refused(cli: Cli, tmp_path: Path) -> None:
    src = _tool(tmp_path / "src")
    (src / "passwd").symlink_to("/etc/passwd")
    refused = cli("lib", "push", str(src), "--kind", "tools", "--name", unique("linked"))
    assert refused.code == 1 and "is a symbolic link" in refused.err
