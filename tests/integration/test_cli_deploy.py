"""`twinlink deploy` run as a subprocess against a real server: a small twin package pushed
with `twinlink lib push`, planned (nothing made), created, started, stopped, reconfigured,
its lifecycle phases run and followed (the exit code the script's), terminated."""

from __future__ import annotations

import json
import textwrap

import pytest

from tests.conftest import Server
from tests.integration._util import unique
from tests.integration.test_cli import Cli

pytestmark = pytest.mark.integration

TWIN_YAML = """
description: A probe twin for the CLI tests
parameters:
  type: object
  properties:
    label: {type: string, default: first}
    limit: {type: number, default: 3}
  additionalProperties: false
document:
  version: "1.0"
  name: ${deployment.name}
  description: "label ${params.label}"
devices:
  - {name: probe, description: a probe}
lifecycle:
  default: {timeout_s: 60}
"""
SCRIPTS = {
    "analyze": 'echo "analyze limit=$TWINLINK_PARAM_LIMIT twin=$TWINLINK_TWIN"\necho warned >&2\n',
    "evolve": "echo evolving\nexit 3\n",
}


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


@pytest.fixture(scope="module")
def package(cli: Cli, tmp_path_factory: pytest.TempPathFactory) -> str:
    root = tmp_path_factory.mktemp("package")
    (root / "twin.yaml").write_text(textwrap.dedent(TWIN_YAML))
    (root / "lifecycle").mkdir()
    for phase, body in SCRIPTS.items():
        script = root / "lifecycle" / phase
        script.write_text("#!/bin/sh\n" + body)
        script.chmod(0o755)
    name = unique("probe")
    cli("lib", "push", str(root), "--kind", "twins", "--name", name, "--tag", "1.0.0").ok()
    return name


def test_plan_create_start_stop_terminate(cli: Cli, package: str) -> None:
    name = unique("dep")
    plan = cli("deploy", "create", f"{package}@1.0.0", "--name", name, "-p", "limit=5",
               "--dry-run").ok().out.splitlines()  # fmt: skip
    assert plan == [
        f"+ twin       {name}",
        "+ device     probe",
        "Plan: 2 to create, 0 to update, 0 to delete, 0 unchanged.",
    ]
    assert name not in cli("deploy", "ls").ok().out  # a dry run stores nothing

    made = cli("deploy", "create", f"{package}@1.0.0", "--name", name, "-p", "limit=5").ok().out
    assert "device probe token (shown once): " in made
    assert made.rstrip().endswith(f"{name}: created")
    shown = json.loads(cli("deploy", "show", name, "--json").ok().out)
    assert shown["parameters"] == {"label": "first", "limit": 5}  # 5 stayed a number
    assert shown["resources"]["devices"] == ["probe"]
    [row] = [line.split() for line in cli("deploy", "ls").ok().out.splitlines() if name in line]
    assert row[:3] == [name, "created", f"{package}@1.0.0"]

    assert cli("deploy", "start", name).ok().out.strip() == f"{name}: running"
    assert cli("deploy", "stop", name).ok().out.strip() == f"{name}: stopped"

    diff = cli("deploy", "update", name, "-p", "label=second", "--dry-run").ok().out
    assert f"~ twin       {name}" in diff and "label first -> label second" in diff
    cli("deploy", "update", name, "-p", "label=second").ok()
    shown = json.loads(cli("deploy", "show", name, "--json").ok().out)
    assert shown["parameters"] == {"label": "second", "limit": 5}  # limit kept

    assert cli("deploy", "terminate", name, "--purge").ok().out.strip() == f"{name}: terminated"


def test_runs_are_followed_and_exit_with_the_scripts_code(cli: Cli, package: str) -> None:
    name = unique("runs")
    cli("deploy", "create", package, "--name", name, "-p", "limit=7").ok()
    analyzed = cli("deploy", "run", name, "analyze", "--follow").ok()
    assert f"analyze limit=7 twin={name}" in analyzed.out
    assert "warned" in analyzed.out  # the script's stderr is in its log
    assert "succeeded (exit code 0)" in analyzed.err

    evolved = cli("deploy", "run", name, "evolve", "--follow")
    assert evolved.code == 3, evolved.err
    assert "evolving" in evolved.out and "failed (exit code 3)" in evolved.err

    runs = cli("deploy", "runs", name).ok().out.splitlines()
    assert runs[0].split()[:4] == ["RUN", "PHASE", "STATE", "EXIT"]
    rows = [line.split() for line in runs[1:]]
    assert [r[1:4] for r in rows] == [["evolve", "failed", "3"], ["analyze", "succeeded", "0"]]
    log = cli("deploy", "logs", rows[1][0]).ok().out
    assert f"analyze limit=7 twin={name}" in log
    followed = cli("deploy", "logs", rows[0][0], "--follow")
    assert followed.code == 3 and "evolving" in followed.out

    queued = cli("deploy", "run", name, "analyze").ok().out
    assert queued.startswith("run ") and " analyze " in queued
    cli("deploy", "terminate", name).ok()


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["deploy", "create", "no-such-package", "--name", "x1"], "no-such-package"),
        (["deploy", "create", "p", "--name", "x2", "-p", "nokey"], "is not key=value"),
        (["deploy", "show", "no-such-deployment"], "(404)"),
        (["deploy", "update", "x3"], "give -p key=value or --package"),
        (["deploy", "create", "x4", "--start"], "--name is needed"),
    ],
)
def test_mistakes_are_said_plainly(cli: Cli, args: list[str], says: str) -> None:
    result = cli(*args)
    assert result.code != 0 and says in result.err, result.err
    assert "Traceback" not in result.err


def test_a_parameter_the_schema_refuses_names_it(cli: Cli, package: str) -> None:
    refused = cli("deploy", "create", package, "--name", unique("bad"), "-p", "limit=lots")
    assert refused.code == 1 and "limit" in refused.err and "Traceback" not in refused.err
