"""Checks that the CAD store's models are real: closed, outward-facing STL meshes and
well-formed STEP files."""

from __future__ import annotations

import re
from collections import Counter


def stl_triangles(text: str) -> list[tuple[tuple[float, ...], list[tuple[float, ...]]]]:
    lines = [line.split() for line in text.splitlines()]
    assert lines[0][0] == "solid" and lines[-1][0] == "endsolid"
    facets = []
    for i, words in enumerate(lines):
        if words[:2] == ["facet", "normal"]:
            assert lines[i + 1] == ["outer", "loop"] and lines[i + 5] == ["endloop"]
            vertices = [tuple(map(float, lines[i + k][1:])) for k in (2, 3, 4)]
            assert all(lines[i + k][0] == "vertex" for k in (2, 3, 4))
            facets.append((tuple(map(float, words[2:])), vertices))
    return facets


def assert_closed_outward_mesh(text: str) -> None:
    facets = stl_triangles(text)
    assert len(facets) > 10
    edges: Counter[tuple[tuple[float, ...], tuple[float, ...]]] = Counter()
    volume = 0.0
    for normal, (a, b, c) in facets:
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        assert sum(n * x for n, x in zip(normal, cross, strict=True)) > 0  # normal agrees
        volume += sum(a[k] * cross_k for k, cross_k in enumerate(_cross(b, c))) / 6
        for p, q in ((a, b), (b, c), (c, a)):
            edges[(p, q)] += 1
    # Watertight and consistently wound: every edge once each way.
    assert all(n == 1 and edges[(q, p)] == 1 for (p, q), n in edges.items())
    assert volume > 0  # faces point outwards


def _cross(b: tuple[float, ...], c: tuple[float, ...]) -> tuple[float, float, float]:
    return (b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0])


def assert_step_file(text: str) -> None:
    assert text.startswith("ISO-10303-21;\nHEADER;") and text.endswith("END-ISO-10303-21;\n")
    assert "FILE_SCHEMA(('AUTOMOTIVE_DESIGN" in text
    data = text.split("DATA;\n", 1)[1].rsplit("ENDSEC;", 1)[0]
    defined = re.findall(r"^#(\d+)=", data, flags=re.MULTILINE)
    assert len(defined) == len(set(defined)) == data.count(";\n")
    assert set(re.findall(r"#(\d+)", data)) == set(defined)  # every reference resolves
    assert data.count("FACETED_BREP(") == 2 and "CLOSED_SHELL" in data
