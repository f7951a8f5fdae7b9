"""twin.yaml read with lines in its errors, and parameters checked against its schema."""

from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.deploy.package import PhaseLimits, checked_parameters, parse_package
from twinlink.deploy.runner import Limits
from twinlink.deploy.runs import PhaseSettings, RunTarget
from twinlink.domain.errors import DocumentError, InvalidInputError

PACKAGE = """\
description: a rig
parameters:
  type: object
  properties:
    zeta: {type: number, default: 0.7, minimum: 0, maximum: 2}
    cutoff: {type: number, default: 5}
    label: {type: string}
  additionalProperties: false
assets:
  beam: lib:common/models/tingen-beam@1.0.0
devices:
  - {name: rig, description: the rig}
processors:
  - {name: smooth, blueprint: lowpass, source: telemetry}
lifecycle:
  default: {timeout_s: 60}
  execute: {timeout_s: 0, memory_mb: 256}
runner_tags: [gpu]
"""


def test_a_package_is_read_whole() -> None:
    package = parse_package(PACKAGE)
    assert package.description == "a rig"
    assert package.assets == {"beam": "lib:common/models/tingen-beam@1.0.0"}
    assert [d["name"] for d in package.devices] == ["rig"]
    assert package.processors[0]["blueprint"] == "lowpass"
    assert package.limits("execute").timeout_s == 0
    assert package.limits("execute").memory_mb == 256
    assert package.limits("analyze").timeout_s == 60  # the package's default
    assert package.runner_tags == ["gpu"]


def test_unknown_keys_are_refused_by_name_and_line() -> None:
    with pytest.raises(DocumentError) as caught:
        parse_package("description: x\nprocesors: []\nextra: 1\n")
    problems = caught.value.problems
    assert [p.path for p in problems] == ["procesors", "extra"]
    assert [p.line for p in problems] == [2, 3]
    assert "unknown key 'procesors'" in problems[0].message


def test_resources_need_unique_names_with_their_lines() -> None:
    text = "processors:\n  - {name: a, blueprint: lowpass}\n  - {name: a, blueprint: lowpass}\n"
    with pytest.raises(DocumentError) as caught:
        parse_package(text)
    (problem,) = caught.value.problems
    assert problem.path == "processors[1].name"
    assert problem.line == 3
    assert "named twice" in problem.message


def test_a_bad_schema_and_bad_phases_are_named() -> None:
    text = (
        "parameters: {type: object, properties: {x: {type: numbr}}}\n"
        "lifecycle: {deploy: {timeout_s: 1}, execute: {timeout_s: -1}}\n"
    )
    with pytest.raises(DocumentError) as caught:
        parse_package(text)
    messages = [p.message for p in caught.value.problems]
    assert any("not a valid JSON Schema" in m for m in messages)
    assert any("unknown phase 'deploy'" in m for m in messages)
    assert any("timeout_s" in m for m in messages)


def test_defaults_are_filled_in_and_given_values_kept() -> None:
    schema = parse_package(PACKAGE).parameters
    assert checked_parameters(schema, {"zeta": 1.5}) == {"zeta": 1.5, "cutoff": 5}
    assert checked_parameters(schema, None) == {"zeta": 0.7, "cutoff": 5}


def test_a_bad_parameter_is_named() -> None:
    schema = parse_package(PACKAGE).parameters
    with pytest.raises(InvalidInputError, match=r"parameter zeta: 3 is greater than"):
        checked_parameters(schema, {"zeta": 3})
    with pytest.raises(InvalidInputError, match=r"'nope' was unexpected"):
        checked_parameters(schema, {"nope": 1})
    with pytest.raises(InvalidInputError, match="takes no parameters"):
        checked_parameters(None, {"zeta": 1})


def test_package_refs_as_deployments_name_them() -> None:
    from twinlink.deploy.loading import package_ref

    assert package_ref("rig@1.0.0", None) == "lib:twins/rig@1.0.0"
    assert package_ref("rig", "common") == "lib:common/twins/rig"
    assert package_ref("twins/rig", "group:ntnu") == "lib:group:ntnu/twins/rig"
    assert package_ref("common/twins/rig@1.0.0", "me") == "lib:common/twins/rig@1.0.0"
    assert package_ref("lib:common/twins/rig", None) == "lib:common/twins/rig"
    with pytest.raises(InvalidInputError):
        package_ref("", None)


def test_what_a_phase_does_not_give_comes_from_the_default_then_the_server() -> None:
    text = PACKAGE.replace(
        "  default: {timeout_s: 60}\n  execute: {timeout_s: 0, memory_mb: 256}\n",
        "  default: {memory_mb: 512}\n  execute: {timeout_s: 0}\n  analyze: {memory_mb: 64}\n",
    )
    package = parse_package(text)
    assert package.limits("execute") == PhaseLimits(0, 512)  # memory: the package's default
    assert package.limits("analyze") == PhaseLimits(None, 64)  # timeout: the server's
    assert package.limits("create") == PhaseLimits(None, 512)
    # As a run's target has them: the server's settings fill what the package leaves out.
    server = Limits(3600, 2048)
    settings = {p: PhaseSettings(v.timeout_s, v.memory_mb) for p, v in package.lifecycle.items()}

    async def prepare(work: Path) -> None:
        pass

    target = RunTarget(1, "rig", "rig", 1, prepare, lifecycle=settings)
    assert target.limits("execute", server) == Limits(0, 512)
    assert target.limits("analyze", server) == Limits(3600, 64)
    assert target.limits("clean", server) == Limits(3600, 512)
