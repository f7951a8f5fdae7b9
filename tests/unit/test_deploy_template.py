"""${...} in twin packages: typed when whole, written in when part of a text, unknown names
reported with where they stand."""

from __future__ import annotations

import pytest

from twinlink.deploy.template import Renderer, Variables, render_all
from twinlink.domain.errors import DocumentError
from twinlink.domain.yamlsource import parse_yaml_stream

VARS = Variables(
    {"zeta": 0.7, "opts": {"n": 3}},
    {"deployment.name": "rig-1", "twin.url": "http://h/twins/rig-1",
     "assets.beam": "lib:common/models/beam@sha256:ab#beam.fmu"},
)  # fmt: skip


def render(value: object) -> object:
    renderer = Renderer(VARS, None, "")
    out = renderer.render(value)
    render_all([renderer])
    return out


def test_a_whole_variable_keeps_its_type() -> None:
    assert render("${params.zeta}") == 0.7
    assert render("${params.opts}") == {"n": 3}
    assert render("${params.opts.n}") == 3
    assert render({"fmu": "${assets.beam}"}) == {"fmu": "lib:common/models/beam@sha256:ab#beam.fmu"}


def test_inside_text_values_are_written_in() -> None:
    assert render("rig ${deployment.name} at ${params.zeta}") == "rig rig-1 at 0.7"
    assert render(["see ${twin.url}/x", 5, None]) == ["see http://h/twins/rig-1/x", 5, None]


def test_a_doubled_dollar_is_a_literal() -> None:
    assert render("cost $${params.zeta} and ${params.zeta}") == "cost ${params.zeta} and 0.7"
    assert render("$${x}") == "${x}"


def test_unknown_variables_are_all_named_with_their_place_and_line() -> None:
    (src,) = parse_yaml_stream(
        "processors:\n  - params:\n      parameters:\n        zeta: ${params.zeda}\n"
        "        k: x ${twin.nope}\n"
    )
    renderer = Renderer(VARS, src, "")
    renderer.render(src.data["processors"], ("processors",))
    with pytest.raises(DocumentError) as caught:
        render_all([renderer])
    problems = caught.value.problems
    assert [p.path for p in problems] == [
        "processors[0].params.parameters.zeta",
        "processors[0].params.parameters.k",
    ]
    assert "unknown variable ${params.zeda}" in problems[0].message
    assert problems[0].line == 4


def test_an_unclosed_variable_is_refused() -> None:
    renderer = Renderer(VARS, None, "")
    renderer.render({"a": "x ${params.zeta"}, ())
    with pytest.raises(DocumentError, match="without a closing"):
        render_all([renderer])
