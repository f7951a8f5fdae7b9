"""The server-rendered twin page (`/twins/{slug}` as HTML): values printed as the document's
YAML and JSON write them, nesting kept (tables for entries of one shape), every value escaped,
and links to the web app and the site's icon."""

from __future__ import annotations

import math
import re

import pytest

from twinlink.web.render import index_page, number_text, page, twin_page


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (2.1e11, "2.1e11"),
        (210000000000.5, "210000000000.5"),
        (1e6, "1e6"),
        (1234567.0, "1234567.0"),
        (-3e9, "-3e9"),
        (7850.0, "7850.0"),
        (9.72, "9.72"),
        (0.1, "0.1"),
        (2.1e-12, "2.1e-12"),
        (1e-5, "1e-5"),
        (1.5e300, "1.5e300"),
        (math.inf, ".inf"),
        (-math.inf, "-.inf"),
        (math.nan, ".nan"),
    ],
)
def test_floats_as_yaml_writes_them(value: float, text: str) -> None:
    assert number_text(value) == text
    if math.isfinite(value):
        assert float(text) == value  # the same number, read back


def _cells(html: str) -> list[str]:
    return re.findall(r"<t[dh](?: [^>]*)?>(.*?)</t[dh]>", html)


DOC = {
    "name": "Tingen",
    "description": "A rig.",
    "privacy": "public",
    "flags": {"enabled": True, "retired": False, "note": None},
    "physicalProperties": {
        "youngsModulus": {"value": 2.1e11, "unit": "Pa"},
        "density": {"value": 7850, "unit": "kg/m^3"},
    },
    "tags": [],
    "interface": {
        "default_device": "rig",
        "signals": [{"name": "angle", "unit": "rad", "min": 0.0, "max": 1.0}],
        "commands": [
            {"name": "pause", "parameters": []},
            {"name": "set_rate", "parameters": [{"name": "value", "required": True}]},
        ],
    },
    "relations": [{"relationType": "parent", "id": "https://x.example/hall", "note": "in hall"}],
}


def test_values_print_as_yaml_and_json_write_them() -> None:
    html = twin_page(DOC, "tingen")
    assert "True" not in html and "False" not in html and "None" not in html
    assert "<dt>enabled</dt><dd>true</dd>" in html
    assert "<dt>retired</dt><dd>false</dd>" in html
    assert "<dt>note</dt><dd><span class=muted>null</span></dd>" in html
    assert "2.1e11" in html and "210000000000" not in html
    assert "<dt>tags</dt><dd><span class=muted>[]</span></dd>" in html


def test_nesting_is_kept_with_tables_for_entries_of_one_shape() -> None:
    html = twin_page(DOC, "tingen")
    # A mapping inside a mapping is a nested list of its own...
    assert "<dt>flags</dt><dd><dl class=nested><dt>enabled</dt>" in html
    # ...and entries of one shape are a table: physical properties by name, signals by row,
    # commands with their parameters in a table of their own.
    physical = html[html.index("<dt>physicalProperties</dt>") :]
    assert _cells(physical)[:6] == ["", "value", "unit", "youngsModulus", "2.1e11", "Pa"]
    interface = html[html.index("<h2>Interface</h2>") :]
    assert "<dt>default_device</dt><dd>rig</dd>" in interface
    assert _cells(interface)[:4] == ["name", "unit", "min", "max"]
    assert _cells(interface)[4:8] == ["angle", "rad", "0.0", "1.0"]
    set_rate = interface[interface.index("set_rate") :]
    assert "<td><table class=values><thead><tr><th>name</th><th>required</th></tr>" in set_rate
    assert "<tr><td>value</td><td>true</td></tr>" in set_rate
    # relations keep their own keys
    relations = html[html.index("<h2>Relations</h2>") :]
    assert "in hall" in relations and 'href="https://x.example/hall"' in relations


def test_links_to_the_web_app_and_names_the_icon() -> None:
    html = twin_page(DOC, "tingen")
    assert '<a href="/app/twins/tingen"><b>Open in the web app</b></a>' in html
    assert '<link rel=icon type="image/svg+xml" href="/favicon.svg">' in html
    assert '<a href="/app/">Web app</a>' in index_page([], signed_in=False)
    assert 'href="/favicon.svg"' in page("x", "")


def test_every_value_is_escaped() -> None:
    evil = "<script>alert(1)</script>"
    html = twin_page(
        {"name": evil, evil: {evil: [{evil: evil}]}, "relations": [{"id": "javascript:x"}]}, evil
    )
    assert "<script>" not in html
    assert 'href="javascript:' not in html
    assert "/app/twins/%3Cscript%3E" in html
