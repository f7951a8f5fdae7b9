// The catalog's relation tree, built from the `relations?direction=down` answers of many twins.
//
// Each answer is one twin's subtree, and the server lists a twin only once per answer, so the
// answers are first merged into one graph (every parent → child edge any answer shows), then
// the forest is unfolded from the twins that are nobody's descendant. The graph may hold cycles
// (A is B's parent and B is A's): a branch stops where a twin is already its own ancestor, and
// the twins of a cycle that no root reaches become roots themselves, so none is lost.

import type { RelationNode } from "../../api/types";

/** A twin as the catalog lists it. */
export interface ListedTwin {
  id: string;
  slug: string;
  name: string;
}

export interface RelationTreeNode {
  /** The path of ids from the root, unique in the forest (a twin may sit under two parents). */
  key: string;
  id: string;
  /** Absent when the related id is not a twin registered here. */
  slug?: string;
  name: string;
  /** A root of the forest, or the child of the node above. */
  relation: "root" | "child";
  /** The twin is already an ancestor on this branch; its children are not repeated. */
  cycle: boolean;
  children: RelationTreeNode[];
}

export interface RelationForest {
  roots: RelationTreeNode[];
  /** Whether any twin has a child at all. */
  hasRelations: boolean;
  /** The forest was cut at `maxNodes` nodes. */
  truncated: boolean;
}

interface RelationGraph {
  info: Map<string, { slug?: string; name: string }>;
  children: Map<string, string[]>;
}

/** Every node and parent → child edge the subtrees show, each once. */
export function mergeSubtrees(twins: ListedTwin[], subtrees: RelationNode[]): RelationGraph {
  const graph: RelationGraph = { info: new Map(), children: new Map() };
  for (const twin of twins) graph.info.set(twin.id, { slug: twin.slug, name: twin.name });
  const visit = (node: RelationNode) => {
    if (!graph.info.has(node.id) || (node.slug && !graph.info.get(node.id)?.slug)) {
      graph.info.set(node.id, { slug: node.slug ?? undefined, name: node.name ?? node.slug ?? node.id });
    }
    const children = graph.children.get(node.id) ?? [];
    for (const child of node.nodes) {
      if (!children.includes(child.id)) children.push(child.id);
      visit(child);
    }
    if (children.length > 0) graph.children.set(node.id, children);
  };
  subtrees.forEach(visit);
  return graph;
}

function reachable(graph: RelationGraph, from: string[]): Set<string> {
  const seen = new Set<string>(from);
  const stack = [...from];
  for (let id = stack.pop(); id !== undefined; id = stack.pop()) {
    for (const child of graph.children.get(id) ?? []) {
      if (!seen.has(child)) {
        seen.add(child);
        stack.push(child);
      }
    }
  }
  return seen;
}

/** The listed twins that are nobody's descendant, then one twin of each cycle none reaches. */
export function findRoots(twins: ListedTwin[], graph: RelationGraph): string[] {
  const descendants = new Set([...graph.children.values()].flat());
  const roots = twins.map((t) => t.id).filter((id) => !descendants.has(id));
  const reached = reachable(graph, roots);
  for (const twin of twins) {
    if (!reached.has(twin.id)) {
      roots.push(twin.id);
      reachable(graph, [twin.id]).forEach((id) => reached.add(id));
    }
  }
  return roots;
}

const byName = (graph: RelationGraph) => (a: string, b: string) =>
  (graph.info.get(a)?.name ?? a).localeCompare(graph.info.get(b)?.name ?? b);

/** The relation forest of the listed `twins`, from their `subtrees` (down), at most `maxNodes`
 * nodes: a twin under two parents appears under both, so a graph of many shared descendants
 * could otherwise unfold into a very large tree. */
export function buildRelationForest(
  twins: ListedTwin[],
  subtrees: RelationNode[],
  maxNodes = 5000,
): RelationForest {
  const graph = mergeSubtrees(twins, subtrees);
  let budget = maxNodes;
  let truncated = false;
  const unfold = (id: string, path: string[]): RelationTreeNode => {
    budget -= 1;
    const info = graph.info.get(id) ?? { name: id };
    const cycle = path.includes(id);
    const node: RelationTreeNode = {
      key: [...path, id].join("\n"),
      id,
      slug: info.slug,
      name: info.name,
      relation: path.length === 0 ? "root" : "child",
      cycle,
      children: [],
    };
    if (cycle) return node;
    for (const child of [...(graph.children.get(id) ?? [])].sort(byName(graph))) {
      if (budget <= 0) {
        truncated = true;
        break;
      }
      node.children.push(unfold(child, [...path, id]));
    }
    return node;
  };
  const roots: RelationTreeNode[] = [];
  for (const id of findRoots(twins, graph).sort(byName(graph))) {
    if (budget <= 0) {
      truncated = true;
      break;
    }
    roots.push(unfold(id, []));
  }
  return { roots, hasRelations: graph.children.size > 0, truncated };
}
