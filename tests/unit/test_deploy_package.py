"""twin.yaml read with lines in its errors, and parameters checked against its schema."""

from __future__ import annotations

import pytest

from twinlink.deploy.package import checked_parameters, parse_package
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
