"""Algebraic loops of a co-simulation, found before it runs and named.

A loop is a cycle of ports in which every value depends on the next one at the same instant:
a connection carries an output to an input at once, and an output that depends directly on
an input (feedthrough, from the FMU's ModelStructure/Outputs dependencies, which FMPy's
read_model_description gives) carries it through the FMU at once. A cycle passing through a
state (an output that depends on no input directly) is not a loop: the state breaks it.

`feedthrough(instance)` gives, per output, the inputs it depends on directly. An output it
does not name, or an instance for which it returns None (no ModelStructure information),
counts as depending directly on every input of its instance: conservative, so a loop is
never missed, though one may be reported that the FMU would break.

One loop is named per strongly connected group of ports, the shortest found from its first
port: enough to say where the system must be cut, where listing every cycle of a dense group
could take exponential time.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from twinlink.cosim.model import Port, System

Feedthrough = Callable[[str], Mapping[str, set[str]] | None]


@dataclass(slots=True)
class _Graph:
    edges: dict[Port, list[Port]]

    def add(self, a: Port, b: Port) -> None:
        self.edges.setdefault(a, []).append(b)
        self.edges.setdefault(b, [])


def feedthrough_of(model_description: Any) -> dict[str, set[str]]:
    """An FMU's feedthrough from FMPy's read_model_description: per output, the inputs its
    ModelStructure says it depends on. An output without a `dependencies` attribute is left
    out, so it counts as depending on every input; a dependency on a state or a parameter
    is no feedthrough (a connection never feeds those)."""
    out: dict[str, set[str]] = {}
    for unknown in model_description.outputs:
        if unknown.dependencies is None:
            continue
        out[unknown.variable.name] = {
            v.name for v in unknown.dependencies if v.causality == "input"
        }
    return out


def _graph(system: System, feedthrough: Feedthrough) -> _Graph:
    graph = _Graph({})
    inputs: dict[str, set[str]] = {}
    outputs: dict[str, set[str]] = {}
    for conn in system.connections:
        graph.add(conn.source, conn.target)
        outputs.setdefault(conn.source.instance, set()).add(conn.source.variable)
        inputs.setdefault(conn.target.instance, set()).add(conn.target.variable)
    # only outputs and inputs that are connected can be on a loop
    for inst, outs in outputs.items():
        ins = inputs.get(inst, set())
        if not ins:
            continue
        deps = feedthrough(inst)
        for out in sorted(outs):
            direct = ins if deps is None or out not in deps else deps[out] & ins
            for var in sorted(direct):
                graph.add(Port(inst, var), Port(inst, out))
    return graph


def _components(graph: _Graph) -> list[list[Port]]:
    """Tarjan's strongly connected components, iteratively (a long chain of FMUs must not
    reach Python's recursion limit)."""
    index: dict[Port, int] = {}
    low: dict[Port, int] = {}
    stack: list[Port] = []
    on_stack: set[Port] = set()
    found: list[list[Port]] = []
    for root in graph.edges:
        if root in index:
            continue
        work: list[tuple[Port, int]] = [(root, 0)]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, i = work[-1]
            nexts = graph.edges[node]
            if i < len(nexts):
                work[-1] = (node, i + 1)
                nxt = nexts[i]
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, 0))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                group: list[Port] = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                found.append(group)
    return found


def _shortest_cycle(graph: _Graph, group: Iterable[Port], start: Port) -> list[Port]:
    """The shortest cycle through `start` inside `group` (breadth first)."""
    members = set(group)
    parent: dict[Port, Port] = {}
    frontier = [start]
    while frontier:
        following: list[Port] = []
        for node in frontier:
            for nxt in graph.edges[node]:
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(parent[path[-1]])
                    return path[::-1]
                if nxt in members and nxt not in parent:
                    parent[nxt] = node
                    following.append(nxt)
        frontier = following
    return [start]  # not reached: a strongly connected group has a cycle through each port


def algebraic_loops(system: System, feedthrough: Feedthrough) -> list[list[Port]]:
    """The system's algebraic loops, each as its ports in order from an output (the last
    port feeds the first), ordered by their first port's name; none, an empty list."""
    graph = _graph(system, feedthrough)
    outputs = {c.source for c in system.connections}
    loops: list[list[Port]] = []
    for group in _components(graph):
        if len(group) == 1 and group[0] not in graph.edges[group[0]]:
            continue
        start = min((p for p in group if p in outputs), key=str, default=min(group, key=str))
        loops.append(_shortest_cycle(graph, group, start))
    return sorted(loops, key=lambda loop: str(loop[0]))


def describe_loop(loop: list[Port]) -> str:
    """A loop as a person reads it: "a.y -> b.u -> b.y -> a.u -> a.y"."""
    return " -> ".join(str(p) for p in [*loop, loop[0]])
