"""`twinlink lib import-dtaas` against a real server: a DTaaS digital twin folder (laid out as
DTaaS's mass-spring-damper: description, README, two config files, lifecycle scripts, one
without the executable bit) imported unchanged, its config files a data asset of their own,
and every lifecycle phase it has runnable with `twinlink deploy run`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from tests.conftest import EXAMPLES, Server
from tests.integration._util import unique
from tests.integration.test_cli import Cli
from tests.unit.test_client_dtaas import dtaas_folder

pytestmark = pytest.mark.integration

SCRIPTS = {
    # As DTaaS scripts do: work relative to the twin's folder, read its config files.
    "create": 'cd "$(dirname "$0")/.."\nmkdir -p output\necho "created in $(basename "$PWD")"\n',
    "execute": (
        'cd "$(dirname "$0")/.."\n'
        "python3 -c \"import json; print('endTime', json.load(open('time.json'))['endTime'])\"\n"
        "cmp time.json assets/config/time.json && echo 'config asset: same file'\n"
    ),
    "clean": "echo cleaned\nexit 4\n",
}


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


def _twin(root: Path) -> Path:
    dtaas_folder(root)
    for phase, body in SCRIPTS.items():
        (root / "lifecycle" / phase).write_text("#!/bin/bash\n" + body)
    return root


def test_a_dtaas_twin_imports_unchanged_and_its_phases_run(cli: Cli, tmp_path: Path) -> None:
    src = _twin(tmp_path / "mass-spring-damper")
    name = unique("msd")
    imported = cli("lib", "import-dtaas", str(src), "--name", name, "--tag", "1.0.0").ok()
    lines = imported.out.splitlines()
    assert lines[0].startswith(f"pushed user:admin/data/{name}-config@sha256:")
    assert "(2 files," in lines[0]
    assert lines[1].startswith(f"pushed user:admin/twins/{name}@sha256:")
    assert "(10 files," in lines[1]  # the folder's 9 files and twin.yaml
    assert lines[2] == "lifecycle phases: create, execute, clean"

    pulled = tmp_path / "pulled"
    cli("lib", "pull", f"twins/{name}@1.0.0", "-o", str(pulled)).ok()
    for path in src.rglob("*"):
        if path.is_file():  # every file unchanged
            assert (pulled / path.relative_to(src)).read_bytes() == path.read_bytes(), path
    package = yaml.safe_load((pulled / "twin.yaml").read_text())
    assert package["description"] == "Two mass spring dampers coupled in a co-simulation ${x}."
    config_ref = package["assets"]["config"]
    assert config_ref.startswith(f"lib:user:admin/data/{name}-config@sha256:")
    config = json.loads(cli("lib", "show", config_ref + "", "--json").ok().out)
    assert sorted(f["path"] for f in config["files"]) == ["cosim.json", "time.json"]
    asset = json.loads(cli("lib", "show", f"twins/{name}", "--json").ok().out)
    assert asset["description"] == package["description"]

    deployment = unique("msd")
    cli("deploy", "create", f"twins/{name}@1.0.0", "--name", deployment).ok()
    created = cli("deploy", "run", deployment, "create", "--follow").ok()  # not executable
    assert "created in work" in created.out  # the deployment's folder, deployments/<id>/work
    executed = cli("deploy", "run", deployment, "execute", "--follow").ok()
    assert "endTime 10.0" in executed.out and "config asset: same file" in executed.out
    cleaned = cli("deploy", "run", deployment, "clean", "--follow")
    assert cleaned.code == 4 and "cleaned" in cleaned.out
    cli("deploy", "terminate", deployment, "--purge").ok()


def test_the_shipped_example_imports_and_runs(cli: Cli, tmp_path: Path) -> None:
    name = unique("example")
    cli("lib", "import-dtaas", str(EXAMPLES / "library" / "mass-spring-damper"),
        "--name", name).ok()  # fmt: skip
    cli("deploy", "create", f"twins/{name}", "--name", name).ok()
    # As in DTaaS, the phases share the twin's folder: analyze reads what execute wrote.
    for phase in ("create", "execute", "analyze"):
        ran = cli("deploy", "run", name, phase, "--follow").ok()
        assert "succeeded (exit code 0)" in ran.err
    assert "overshoot_percent" in ran.out
    assert "simulating first" not in ran.out  # it found execute's output/results.csv
    cli("deploy", "terminate", name, "--purge").ok()


def test_what_is_not_a_dtaas_twin_is_refused_before_anything_is_pushed(
    cli: Cli, tmp_path: Path
) -> None:
    (tmp_path / "plain").mkdir()
    (tmp_path / "plain" / "README.md").write_text("# nothing to run\n")
    refused = cli("lib", "import-dtaas", str(tmp_path / "plain"))
    assert refused.code == 1 and "has no lifecycle/ scripts" in refused.err
    assert "plain" not in cli("lib", "ls").ok().out
