import { describe, expect, it } from "vitest";
import type { RelationNode } from "../../api/types";
import { buildRelationForest, findRoots, mergeSubtrees, type ListedTwin, type RelationTreeNode } from "./relationForest";

const twin = (name: string): ListedTwin => ({ id: `urn:${name}`, slug: name, name: name.toUpperCase() });
const node = (name: string, nodes: RelationNode[] = []): RelationNode => ({
  id: `urn:${name}`,
  slug: name,
  name: name.toUpperCase(),
  nodes,
});

/** The forest as indented lines: name, relation, and (cycle) where a branch stops. */
function outline(nodes: RelationTreeNode[], depth = 0): string[] {
  return nodes.flatMap((n) => [
    `${"  ".repeat(depth)}${n.name} ${n.relation}${n.cycle ? " (cycle)" : ""}`,
    ...outline(n.children, depth + 1),
  ]);
}

describe("buildRelationForest", () => {
  it("merges the subtrees of all twins and roots them at the twins nobody descends from", () => {
    const twins = ["hall", "crane", "hoist", "rig"].map(twin);
    // each answer is one twin's subtree; the hall's holds the crane's
    const subtrees = [
      node("hall", [node("crane", [node("hoist")])]),
      node("crane", [node("hoist")]),
      node("hoist"),
      node("rig"),
    ];
    const forest = buildRelationForest(twins, subtrees);
    expect(outline(forest.roots)).toEqual(["HALL root", "  CRANE child", "    HOIST child", "RIG root"]);
    expect(forest.hasRelations).toBe(true);
    expect(forest.truncated).toBe(false);
    expect(forest.roots[0]!.children[0]!.slug).toBe("crane");
  });

  it("shows a twin under each of its parents, with keys unique in the forest", () => {
    const twins = ["a", "b", "shared"].map(twin);
    const forest = buildRelationForest(twins, [node("a", [node("shared")]), node("b", [node("shared")]), node("shared")]);
    expect(outline(forest.roots)).toEqual(["A root", "  SHARED child", "B root", "  SHARED child"]);
    const keys = [forest.roots[0]!.children[0]!.key, forest.roots[1]!.children[0]!.key];
    expect(new Set(keys).size).toBe(2);
  });

  it("stops a branch at a cycle, and keeps the twins of a cycle no root reaches", () => {
    const twins = ["a", "b", "c"].map(twin);
    // a → b → a, reached from c, which nobody descends from
    const subtrees = [node("a", [node("b")]), node("b", [node("a")]), node("c", [node("b")])];
    const graph = mergeSubtrees(twins, subtrees);
    expect(findRoots(twins, graph)).toEqual(["urn:c"]);
    const forest = buildRelationForest(twins, subtrees);
    expect(outline(forest.roots)).toEqual(["C root", "  B child", "    A child", "      B child (cycle)"]);

    // x → y → x: both are somebody's descendant, so one of them becomes a root
    const loop = buildRelationForest(["x", "y"].map(twin), [node("x", [node("y")]), node("y", [node("x")])]);
    expect(outline(loop.roots)).toEqual(["X root", "  Y child", "    X child (cycle)"]);
  });

  it("lists related ids that are not twins registered here, by their id", () => {
    const forest = buildRelationForest([twin("hall")], [
      node("hall", [{ id: "http://elsewhere.example/robot", registered: false, nodes: [] }]),
    ]);
    const [child] = forest.roots[0]!.children;
    const robot = "http://elsewhere.example/robot";
    expect(child).toMatchObject({ id: robot, name: robot, relation: "child" });
    expect(child!.slug).toBeUndefined();
  });

  it("is flat without relations, empty without twins, and cut at maxNodes", () => {
    const flat = buildRelationForest(["b", "a"].map(twin), [node("b"), node("a")]);
    expect(outline(flat.roots)).toEqual(["A root", "B root"]);
    expect(flat.hasRelations).toBe(false);
    expect(buildRelationForest([], []).roots).toEqual([]);

    const wide = buildRelationForest([twin("root")], [node("root", ["c1", "c2", "c3", "c4"].map((n) => node(n)))], 3);
    expect(wide.truncated).toBe(true);
    expect(outline(wide.roots)).toEqual(["ROOT root", "  C1 child", "  C2 child"]);
  });
});
