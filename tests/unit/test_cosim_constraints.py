"""Maestro's var-step constraints: read from a multi-model and from the YAML form (errors
naming the key, or the line), written back by to_yaml, and each one's arithmetic on plain
values (the var-step master applies them to real FMUs: tests/integration/test_cosim_varstep.py)."""

from __future__ import annotations

import math
from typing import Any

import pytest

from tests.conftest import ROOT
from twinlink.cosim import constraints
from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import Constraint, CosimFormatError, Port
from twinlink.cosim.yamlform import read_yaml, to_yaml

MSD = ROOT / "tests" / "cosim_files" / "msd"
M1, M2 = "msd1.msd1i", "msd2.msd2i"

ALL_FOUR = {
    "zc": {"type": "zerocrossing", "ports": ["{msd1}.msd1i.x1"], "order": "2", "abstol": 1e-4},
    "bd": {
        "type": "boundeddifference",
        "ports": ["{msd1}.msd1i.x1", "{msd2}.msd2i.fk"],
        "abstol": 1,
        "reltol": 0.5,
        "safety": 0.2,
        "skipDiscrete": False,
    },
    "sr": {"type": "samplingrate", "base": -3, "rate": 250, "startTime": 100},
    "fm": {"type": "fmumaxstepsize"},
}


def maestro(constraints_: Any) -> Any:
    algorithm = {"type": "var-step", "size": [1e-6, 1.0], "initsize": 1e-3}
    return read_maestro(MSD / "mm.json", settings={"algorithm": algorithm | constraints_})


def test_maestros_four_constraints_are_read_as_written() -> None:
    system = maestro({"constraints": ALL_FOUR})
    assert system.algorithm.constraints == (
        Constraint("zc", "zerocrossing", (Port(M1, "x1"),), order=2, abstol=1e-4),
        Constraint(
            "bd",
            "boundeddifference",
            (Port(M1, "x1"), Port(M2, "fk")),
            abstol=1.0,
            reltol=0.5,
            safety=0.2,
            skip_discrete=False,
        ),
        Constraint("sr", "samplingrate", base=-3, rate=250, start_time=100),
        Constraint("fm", "fmumaxstepsize"),
    )


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ({"x": {"type": "nope"}}, r"constraints\.x\.type: 'nope' is not one of zerocrossing"),
        ({"x": {"type": "zerocrossing"}}, r"constraints\.x\.ports: is not a list of ports"),
        (
            {"x": {"type": "zerocrossing", "ports": ["{msd1}.msd1i.x1"] * 3}},
            "takes one port, or two",
        ),
        (
            {"x": {"type": "boundeddifference", "ports": ["{msd9}.a.b"]}},
            r"the FMU \{msd9\} is not in fmus",
        ),
        ({"x": {"type": "zerocrossing", "ports": ["{msd1}.msd1i.x1"], "order": 3}}, "neither 1"),
        ({"x": {"type": "samplingrate", "rate": 0}}, r"constraints\.x\.rate: 0 is not above 0"),
        ({"x": {"type": "samplingrate", "base": 1.5}}, "1.5 is not a whole number"),
        (
            {"x": {"type": "boundeddifference", "ports": ["{msd1}.msd1i.x1"], "abstol": -1}},
            r"abstol: -1 is not a finite number 0 or more",
        ),
        (
            {"x": {"type": "boundeddifference", "ports": ["{msd1}.msd1i.x1"], "safety": 1}},
            "is not a fraction below 1",
        ),
        ([], "is not an object of name"),
    ],
)
def test_a_bad_constraint_is_refused_naming_its_key(body: Any, message: str) -> None:
    with pytest.raises(CosimFormatError, match=message):
        maestro({"constraints": body})


YAML = """\
instances:
  a: MassSpringDamper1.fmu
  b: MassSpringDamper2.fmu
connections:
  a.x1: b.x1
algorithm:
  type: var-step
  size: 0.01
  min_size: 0.0001
  max_size: 0.5
  tolerance: 1.0e-5
  constraints:
    zc: {type: zerocrossing, ports: [a.x1, b.x2], abstol: 0.001}
    sr: {type: samplingrate, base: -1, rate: 5, startTime: 0}
end_time: 10
"""


def test_the_yaml_form_takes_tolerance_and_constraints_and_writes_them_back() -> None:
    system = read_yaml("s.yaml", text=YAML)
    assert system.algorithm.tolerance == 1e-5
    assert system.algorithm.constraints == (
        Constraint("zc", "zerocrossing", (Port("a", "x1"), Port("b", "x2")), abstol=0.001),
        Constraint("sr", "samplingrate", base=-1, rate=5, start_time=0),
    )
    again = read_yaml("again.yaml", text=to_yaml(system))
    assert again == system
    maestro_system = maestro({"constraints": ALL_FOUR})
    assert read_yaml("m.yaml", text=to_yaml(maestro_system)).algorithm == maestro_system.algorithm


def test_yaml_errors_give_the_line() -> None:
    text = YAML.replace("ports: [a.x1, b.x2]", "ports: [a.x1, c.x2]")
    with pytest.raises(CosimFormatError, match=r"s\.yaml: .*line 13.*'c\.x2' is not instance"):
        read_yaml("s.yaml", text=text)
    text = YAML.replace("type: var-step", "type: fixed-step")
    with pytest.raises(CosimFormatError, match="applies to a var-step algorithm only"):
        read_yaml("s.yaml", text=text)
    with pytest.raises(CosimFormatError, match="tolerance: 0 is not a step size above 0"):
        read_yaml("s.yaml", text=YAML.replace("1.0e-5", "0"))


class Value:
    """A port's value the test sets between steps."""

    def __init__(self, value: float) -> None:
        self.value = value

    def __call__(self) -> float:
        return self.value


def test_sampling_points_bound_each_step() -> None:
    sr = constraints._Sampling(Constraint("sr", "samplingrate", base=-1, rate=5, start_time=3))
    assert sr.bound(0.0, 1.0) == 0.3  # the first sample
    assert sr.bound(0.0, 0.2) == 0.2  # before it: the step as it is
    assert sr.bound(0.3, 1.0) == 0.8  # landed on one: the next
    assert sr.bound(0.3 + 0.5 * 7, 10.0) == 4.3
    assert sr.bound(0.7999, 10.0) == 0.8
    assert sr.bound(0.8 - 1e-12, 10.0) == 1.3  # on it, to rounding: no sliver of a step


def test_a_zero_crossing_is_predicted_and_a_step_over_it_redone() -> None:
    x = Value(1.0)
    zc = constraints._ZeroCrossing(Constraint("zc", "zerocrossing", (), abstol=1e-3), x, 1e-6)
    zc.start(0.0)
    assert zc.bound(0.0, 1.0) == 1.0  # one point: nothing to predict from
    x.value = 0.8  # falling 0.2 a second
    assert zc.retry(0.0, 1.0) is None
    zc.accept(1.0, 1.0)
    assert zc.bound(1.0, 10.0) == pytest.approx(5.0)  # the line reaches zero at 5 s
    assert zc.bound(1.0, 3.0) == 3.0
    x.value = -0.2  # a step of 4.5 s went 0.2 past it: redone to the interpolated crossing
    assert zc.retry(1.0, 4.5) == pytest.approx(4.5 * 0.8 / 1.0)
    x.value = -0.0005  # within the tolerance: kept
    assert zc.retry(1.0, 4.0) is None


def test_a_quadratic_prediction_follows_the_curve() -> None:
    x = Value(4.0)  # f = 4 - t^2 crosses at 2
    zc = constraints._ZeroCrossing(Constraint("zc", "zerocrossing", (), order=2), x, 1e-6)
    zc.start(0.0)
    for t in (0.5, 1.0):
        x.value = 4 - t * t
        zc.accept(t, 0.5)
    assert zc.bound(1.0, 10.0) == pytest.approx(2.0)
    linear = constraints._ZeroCrossing(Constraint("zc", "zerocrossing", ()), x, 1e-6)
    linear.points = zc.points
    assert linear.bound(1.0, 10.0) == pytest.approx(1.0 + 3.0 / 1.5)  # the chord's 3 s


def test_a_bounded_difference_sizes_the_next_step_and_redoes_one_over_it() -> None:
    x = Value(10.0)
    bd = constraints._BoundedDifference(
        Constraint("bd", "boundeddifference", (), abstol=0.1, reltol=0.01, safety=0.0), [x], 0.05
    )
    bd.start(0.0)
    assert bd.bound(0.0, 5.0) == 5.0
    x.value = 10.4  # over max(0.1, 0.104): redone at 0.104 / 0.4 of the step
    assert bd.retry(0.0, 1.0) == pytest.approx(0.104 / 0.4)
    x.value = 10.05
    assert bd.retry(0.0, 1.0) is None
    bd.accept(1.0, 1.0)
    assert bd.bound(1.0, 10.0) == pytest.approx(1.0 + 0.1005 / 0.05)
    x.value = 10.05  # no change: no bound
    bd.accept(2.0, 1.0)
    assert bd.bound(2.0, 10.0) == 10.0 and math.isinf(bd.next_h)
    x.value = 1e6  # a jump (100 times the bound): the next step at least min_size (0.05)
    bd.accept(3.0, 1.0)
    assert bd.bound(3.0, 10.0) == 3.05


def test_a_predicted_crossing_nearer_than_min_size_is_stepped_at_min_size() -> None:
    x = Value(1e-2)
    zc = constraints._ZeroCrossing(Constraint("zc", "zerocrossing", (), abstol=1e-12), x, 1e-3)
    zc.start(0.0)
    x.value = 1e-9  # falling fast: zero predicted 1e-9 s ahead
    zc.accept(1e-2, 1e-2)
    assert zc.bound(1e-2, 1.0) == pytest.approx(1e-2 + 1e-3)
