"""Writing planar solids as a STEP file (ISO 10303-21, AP214 schema): one product whose shape is
a FACETED_BREP_SHAPE_REPRESENTATION. AP214's rules want each face to be a FACE_SURFACE on a
PLANE bounded by POLY_LOOPs, so every face gets its own plane placement."""

from __future__ import annotations

import math
from collections.abc import Sequence

Vec = tuple[float, float, float]
Loop = tuple[Vec, ...]
Face = tuple[Loop, ...]

# Fixed, so that the same model always gives the same bytes (and sha256).
TIMESTAMP = "2024-01-01T00:00:00"


def _real(x: float) -> str:
    text = f"{x:.6f}".rstrip("0")
    text = "0." if text in ("-0.", "0.") else text
    return text


def _cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit(v: Vec) -> Vec:
    length = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    return (v[0] / length, v[1] / length, v[2] / length)


def _sub(a: Vec, b: Vec) -> Vec:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self._points: dict[Vec, int] = {}

    def add(self, entity: str) -> int:
        self.lines.append(f"#{len(self.lines) + 1}={entity};")
        return len(self.lines)

    def point(self, p: Vec) -> int:
        if p not in self._points:
            coords = ",".join(_real(c) for c in p)
            self._points[p] = self.add(f"CARTESIAN_POINT('',({coords}))")
        return self._points[p]

    def direction(self, d: Vec) -> int:
        return self.add(f"DIRECTION('',({','.join(_real(c) for c in d)}))")

    def face(self, face: Face) -> int:
        outer = face[0]
        # Newell's method would be more general; these faces are convex, so three points do.
        normal = _unit(_cross(_sub(outer[1], outer[0]), _sub(outer[2], outer[0])))
        ref = _unit(_sub(outer[1], outer[0]))
        placement = self.add(
            f"AXIS2_PLACEMENT_3D('',#{self.point(outer[0])},"
            f"#{self.direction(normal)},#{self.direction(ref)})"
        )
        plane = self.add(f"PLANE('',#{placement})")
        bounds = []
        for k, loop in enumerate(face):
            points = ",".join(f"#{self.point(p)}" for p in loop)
            poly = self.add(f"POLY_LOOP('',({points}))")
            kind = "FACE_OUTER_BOUND" if k == 0 else "FACE_BOUND"
            bounds.append(self.add(f"{kind}('',#{poly},.T.)"))
        refs = ",".join(f"#{b}" for b in bounds)
        return self.add(f"FACE_SURFACE('',({refs}),#{plane},.T.)")

    def solid(self, faces: Sequence[Face]) -> int:
        refs = ",".join(f"#{self.face(f)}" for f in faces)
        shell = self.add(f"CLOSED_SHELL('',({refs}))")
        return self.add(f"FACETED_BREP('',#{shell})")


def _product(w: _Writer, name: str, description: str) -> tuple[int, int]:
    """The product entities; returns (its product definition shape, the geometric context)."""
    app = w.add("APPLICATION_CONTEXT('automotive design')")
    w.add(
        f"APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    )
    context = w.add(f"PRODUCT_CONTEXT('',#{app},'mechanical')")
    product = w.add(f"PRODUCT('{name}','{description}','',(#{context}))")
    formation = w.add(f"PRODUCT_DEFINITION_FORMATION('1','',#{product})")
    def_context = w.add(f"PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')")
    definition = w.add(f"PRODUCT_DEFINITION('design','',#{formation},#{def_context})")
    shape = w.add(f"PRODUCT_DEFINITION_SHAPE('','',#{definition})")
    mm = w.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))")
    rad = w.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))")
    sr = w.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())")
    accuracy = w.add(
        f"UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-05),#{mm},"
        "'distance_accuracy_value','confusion accuracy')"
    )
    geometry = w.add(
        f"(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{accuracy}))"
        f"GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm},#{rad},#{sr}))REPRESENTATION_CONTEXT('',''))"
    )
    return shape, geometry


def step_file(name: str, description: str, solids: Sequence[Sequence[Face]]) -> str:
    w = _Writer()
    shape, geometry = _product(w, name, description)
    origin = w.add(
        f"AXIS2_PLACEMENT_3D('',#{w.point((0.0, 0.0, 0.0))},"
        f"#{w.direction((0.0, 0.0, 1.0))},#{w.direction((1.0, 0.0, 0.0))})"
    )
    breps = [w.solid(faces) for faces in solids]
    items = ",".join(f"#{i}" for i in (origin, *breps))
    representation = w.add(f"FACETED_BREP_SHAPE_REPRESENTATION('{name}',({items}),#{geometry})")
    w.add(f"SHAPE_DEFINITION_REPRESENTATION(#{shape},#{representation})")
    header = [
        "ISO-10303-21;",
        "HEADER;",
        f"FILE_DESCRIPTION(('{description}'),'2;1');",
        f"FILE_NAME('{name}.step','{TIMESTAMP}',('twinlink'),('twinlink'),"
        "'twinlink crane CAD generator','twinlink','');",
        "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));",
        "ENDSEC;",
        "DATA;",
    ]
    return "\n".join([*header, *w.lines, "ENDSEC;", "END-ISO-10303-21;"]) + "\n"
