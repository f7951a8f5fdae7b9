"""Algebraic loops found before a co-simulation runs (cosim/graph.py), on small systems and
on an FMU's ModelStructure as FMPy reads it."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from fmpy import read_model_description

from twinlink.cosim.graph import algebraic_loops, describe_loop, feedthrough_of
from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System

FILES = Path(__file__).resolve().parents[1] / "cosim_files"


def system(*links: str) -> System:
    """A system from "a.y->b.u" links; an instance per name seen."""
    connections = []
    for link in links:
        src, dst = (Port(*end.split(".")) for end in link.split("->"))
        connections.append(Connection(src, dst))
    names = sorted({p.instance for c in connections for p in (c.source, c.target)})
    return System(
        instances=tuple(Instance(n, f"{n}.fmu") for n in names),
        connections=tuple(connections),
        parameters={},
        log_variables={},
        algorithm=Algorithm("fixed-step", 0.1),
    )


def table(
    deps: Mapping[str, Mapping[str, set[str]] | None],
) -> Callable[[str], Mapping[str, set[str]] | None]:
    return lambda instance: deps.get(instance, {})


def texts(loops: list[list[Port]]) -> list[str]:
    return [describe_loop(loop) for loop in loops]


def test_a_two_fmu_loop_through_feedthrough_is_named() -> None:
    s = system("a.y->b.u", "b.y->a.u")
    loops = algebraic_loops(s, table({"a": {"y": {"u"}}, "b": {"y": {"u"}}}))
    assert texts(loops) == ["a.y -> b.u -> b.y -> a.u -> a.y"]
    assert loops[0] == [Port("a", "y"), Port("b", "u"), Port("b", "y"), Port("a", "u")]


def test_a_state_breaks_the_loop() -> None:
    s = system("a.y->b.u", "b.y->a.u")
    # b's output depends on its state only: the classic mass-spring-damper coupling
    assert algebraic_loops(s, table({"a": {"y": {"u"}}, "b": {"y": set()}})) == []


def test_no_connections_no_loops() -> None:
    assert algebraic_loops(system(), table({})) == []
    assert algebraic_loops(system("a.y->b.u", "b.y->c.u"), lambda _: None) == []


def test_unknown_dependencies_count_as_direct() -> None:
    s = system("a.y->b.u", "b.y->a.u")
    # b says nothing (None: no ModelStructure); a names y's inputs
    loops = algebraic_loops(s, table({"a": {"y": {"u"}}, "b": None}))
    assert texts(loops) == ["a.y -> b.u -> b.y -> a.u -> a.y"]
    # an output missing from an instance's mapping counts as direct too
    loops = algebraic_loops(s, table({"a": {"y": {"u"}}, "b": {"other": set()}}))
    assert len(loops) == 1


def test_a_self_loop_through_one_fmu() -> None:
    s = system("a.y->a.u")
    assert texts(algebraic_loops(s, table({"a": {"y": {"u"}}}))) == ["a.y -> a.u -> a.y"]


def test_only_the_inputs_an_output_depends_on_close_a_loop() -> None:
    # a.y depends on a.v only; the loop through a.u is broken, the one through a.v is not
    s = system("a.y->b.u", "b.y->a.u", "b.z->a.v")
    ft = table({"a": {"y": {"v"}}, "b": {"y": {"u"}, "z": {"u"}}})
    assert texts(algebraic_loops(s, ft)) == ["a.y -> b.u -> b.z -> a.v -> a.y"]


def test_separate_loops_each_named_and_a_chain_beside_them() -> None:
    loop1 = ["a.y->b.u", "b.y->a.u"]
    loop2 = ["c.y->d.u", "d.y->e.u", "e.y->c.u"]  # three FMUs
    chain = ["b.y->f.u", "f.y->g.u"]  # fed by loop 1, no loop of its own
    s = system(*loop1, *loop2, *chain)
    direct = table({n: {"y": {"u"}} for n in "abcdefg"})
    assert texts(algebraic_loops(s, direct)) == [
        "a.y -> b.u -> b.y -> a.u -> a.y",
        "c.y -> d.u -> d.y -> e.u -> e.y -> c.u -> c.y",
    ]


def test_a_long_chain_closed_into_a_loop_needs_no_recursion() -> None:
    n = 3000  # past Python's recursion limit for a recursive search
    links = [f"m{i}.y->m{i + 1}.u" for i in range(n)] + [f"m{n}.y->m0.u"]
    loops = algebraic_loops(system(*links), lambda _: None)
    assert len(loops) == 1
    assert len(loops[0]) == 2 * (n + 1)


def test_feedthrough_from_fmpys_model_description() -> None:
    md = read_model_description(str(FILES / "feedthrough" / "modelDescription.xml"))
    ft = feedthrough_of(md)
    # y1 depends on u1 (and a parameter, no feedthrough), y2 on the state only, y3 unknown
    assert ft == {"y1": {"u1"}, "y2": set()}
    s = system("f.y1->g.u", "g.y->f.u1", "f.y2->h.u", "h.y->f.u1", "f.y3->k.u", "k.y->f.u2")
    loops = algebraic_loops(s, lambda inst: ft if inst == "f" else {"y": {"u"}})
    # the loop through h is broken by y2's state; y3, unknown, closes the one through k
    assert texts(loops) == [
        "f.y1 -> g.u -> g.y -> f.u1 -> f.y1",
        "f.y3 -> k.u -> k.y -> f.u2 -> f.y3",
    ]


def test_the_mass_spring_damper_pair_has_a_loop_only_if_both_feed_through() -> None:
    msd = read_maestro(FILES / "msd" / "maestro2.json")
    # msd1 outputs its position and speed (states), msd2 the force from them (direct)
    ft = {"msd1.msd1i": {"x1": set(), "v1": set()}, "msd2.msd2i": {"fk": {"x1", "v1"}}}
    assert algebraic_loops(msd, table(ft)) == []
    assert texts(algebraic_loops(msd, lambda _: None)) == [
        "msd1.msd1i.v1 -> msd2.msd2i.v1 -> msd2.msd2i.fk -> msd1.msd1i.fk -> msd1.msd1i.v1"
    ]
