"""The fixed-step master's schedule: the Gauss-Seidel order and the communication points."""

from __future__ import annotations

import pytest

from twinlink.cosim.master import stepping_order, steps
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System


def system(names: str, links: list[str], step: float = 0.1, end: float = 1.0) -> System:
    """`links` as "a>b": an output of a feeds an input of b."""

    def connection(link: str) -> Connection:
        a, b = link.split(">")
        return Connection(Port(a, "y"), Port(b, "u"))

    return System(
        instances=tuple(Instance(n, f"{n}.fmu") for n in names.split()),
        connections=tuple(connection(link) for link in links),
        parameters={},
        log_variables={},
        algorithm=Algorithm("fixed-step", step),
        end_time=end,
    )


@pytest.mark.parametrize(
    ("names", "links", "order"),
    [
        ("c b a", ["a>b", "b>c"], ("a", "b", "c")),  # a chain, whatever the declared order
        ("plant ctrl", ["plant>ctrl", "ctrl>plant"], ("plant", "ctrl")),  # a cycle: declared
        ("ctrl plant", ["plant>ctrl", "ctrl>plant"], ("ctrl", "plant")),
        ("x a b", ["b>a", "a>b", "a>x"], ("a", "x", "b")),  # x, fed by the cycle, waits for a
        ("c d a b", ["a>b", "b>a", "b>c", "c>d", "d>c"], ("a", "b", "c", "d")),  # cycle by cycle
        ("p q", ["p>p"], ("p", "q")),  # feeding itself orders nothing
    ],
)
def test_gauss_seidel_steps_an_instance_after_those_that_feed_it(
    names: str, links: list[str], order: tuple[str, ...]
) -> None:
    assert stepping_order(system(names, links)) == order


def test_the_last_step_is_shorter_when_the_span_is_not_whole_steps() -> None:
    assert steps(system("a", [], step=0.4, end=1.0)) == pytest.approx([0.0, 0.4, 0.8, 1.0])
    points = steps(system("a", [], step=0.1, end=1.0))  # 10 steps despite 0.1's rounding
    assert len(points) == 11 and points[-1] == 1.0
