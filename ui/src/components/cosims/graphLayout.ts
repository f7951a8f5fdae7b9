// Where the connection graph of a co-simulation draws its boxes and arrows: instances in
// layers (columns, left to right) following the connections, as a layered ("Sugiyama") drawing
// does it, small enough to do by hand. Cycles are usual in a co-simulation (a mass gives a
// spring its position, the spring gives the mass its force): a depth-first search marks the
// connections that close a cycle, those go right to left below the boxes and the rest set the
// layers. The connections of an algebraic loop, as the server found them, are marked.
import type { CosimConnection } from "../../api/cosims";

export interface Port {
  instance: string;
  variable: string;
}

export interface GraphInput {
  instances: string[];
  connections: CosimConnection[];
  /** Each loop's ports in order from an output; the last feeds the first. */
  loops: string[][];
}

export interface Box {
  name: string;
  layer: number;
  x: number;
  y: number;
  width: number;
  height: number;
  /** Part of an algebraic loop. */
  inLoop: boolean;
}

export type EdgeKind = "forward" | "over" | "back" | "self";

export interface Edge {
  from: string;
  to: string;
  /** One per connection: "x1", or "fk → force" when the two variables' names differ. */
  labels: string[];
  /** What is written on the arrow: the labels, the first few of a long list. */
  text: string;
  kind: EdgeKind;
  inLoop: boolean;
  /** The SVG path, drawn from `from` to `to` (the arrowhead at its end). */
  path: string;
  labelX: number;
  labelY: number;
  labelWidth: number;
}

export interface Layout {
  width: number;
  height: number;
  boxes: Box[];
  edges: Edge[];
}

/** About the width of a character of the graph's 12 px font; text is never measured (the
 * layout is computed before anything is drawn, and in tests). */
export const CHAR_W = 7;
export const BOX_H = 36;
const BOX_MIN_W = 90;
const BOX_PAD = 24;
const ROW_GAP = 34;
const COL_GAP_MIN = 110;
const MARGIN = 24;
const LABEL_MAX = 3;
/** How far an arc (back below, over above) clears the boxes, and the step between levels. */
const ARC_DEPTH = 26;
const ARC_STEP = 18;
/** How far a back arrow leaves and arrives below a box's middle, an arc over above it. */
const BACK_DROP = 8;
const OVER_RISE = 8;
/** How far into the gap beside a box an arc turns (arcs below and above in lanes of their
 * own, each level one lane further), and the radius of its turns. */
const LEAD_BACK = 10;
const LEAD_OVER = 18;
const LANE = 6;
const CORNER = 6;
const SELF_RISE = 30;

/** A port from the API: the longest instance name that prefixes it with a dot is the instance
 * ("msd1.m1.x1" of "msd1.m1" is x1), else it splits at the last dot. */
export function splitPort(ref: string, instances: readonly string[]): Port {
  let best = "";
  for (const name of instances) {
    if (name.length > best.length && ref.startsWith(`${name}.`)) best = name;
  }
  if (best) return { instance: best, variable: ref.slice(best.length + 1) };
  const dot = ref.lastIndexOf(".");
  return dot > 0 ? { instance: ref.slice(0, dot), variable: ref.slice(dot + 1) } : { instance: ref, variable: "" };
}

const portKey = (p: Port) => `${p.instance}\u0000${p.variable}`;
const edgeKey = (from: string, to: string) => `${from}\u0000${to}`;

/** The connections in an algebraic loop: an output followed by the input it feeds. */
function loopConnections(loops: string[][], instances: readonly string[]): Set<string> {
  const marked = new Set<string>();
  for (const loop of loops) {
    const ports = loop.map((p) => splitPort(p, instances));
    ports.forEach((a, i) => {
      const b = ports[(i + 1) % ports.length] as Port;
      marked.add(`${portKey(a)}\u0001${portKey(b)}`);
    });
  }
  return marked;
}

interface Grouped {
  from: string;
  to: string;
  labels: string[];
  inLoop: boolean;
}

/** One edge per ordered pair of instances, with every connection's label, in input order. */
function groupConnections(input: GraphInput, names: readonly string[]): Grouped[] {
  const inLoop = loopConnections(input.loops, names);
  const edges = new Map<string, Grouped>();
  for (const c of input.connections) {
    const s = splitPort(c.source, names);
    const t = splitPort(c.target, names);
    const key = edgeKey(s.instance, t.instance);
    const edge = edges.get(key) ?? { from: s.instance, to: t.instance, labels: [], inLoop: false };
    edge.labels.push(s.variable === t.variable ? s.variable : `${s.variable} → ${t.variable}`);
    edge.inLoop ||= inLoop.has(`${portKey(s)}\u0001${portKey(t)}`);
    edges.set(key, edge);
  }
  return [...edges.values()];
}

/** The edges that close a cycle (depth-first from each instance in order: an edge to an
 * instance still on the stack), so that the others form a DAG. */
export function backEdges(names: readonly string[], edges: readonly { from: string; to: string }[]): Set<string> {
  const out = new Map<string, string[]>(names.map((n) => [n, []]));
  for (const e of edges) if (e.from !== e.to) out.get(e.from)?.push(e.to);
  const state = new Map<string, "open" | "done">();
  const back = new Set<string>();
  // Iterative, so that a long chain of instances does not grow the call stack.
  for (const root of names) {
    if (state.has(root)) continue;
    const stack: [string, number][] = [[root, 0]];
    state.set(root, "open");
    while (stack.length) {
      const top = stack[stack.length - 1] as [string, number];
      const [node, next] = top;
      const targets = out.get(node) ?? [];
      if (next >= targets.length) {
        state.set(node, "done");
        stack.pop();
        continue;
      }
      top[1] = next + 1;
      const target = targets[next] as string;
      const seen = state.get(target);
      if (seen === "open") back.add(edgeKey(node, target));
      else if (!seen) {
        state.set(target, "open");
        stack.push([target, 0]);
      }
    }
  }
  return back;
}

/** Longest-path layers over the edges that are not back edges: each instance one column right
 * of the furthest instance that feeds it. */
export function layers(names: readonly string[], forward: readonly { from: string; to: string }[]): Map<string, number> {
  const incoming = new Map<string, string[]>(names.map((n) => [n, []]));
  const outgoing = new Map<string, string[]>(names.map((n) => [n, []]));
  for (const e of forward) {
    incoming.get(e.to)?.push(e.from);
    outgoing.get(e.from)?.push(e.to);
  }
  const layer = new Map<string, number>();
  const waiting = new Map(names.map((n) => [n, incoming.get(n)?.length ?? 0]));
  const ready = names.filter((n) => waiting.get(n) === 0);
  while (ready.length) {
    const node = ready.shift() as string;
    const here = Math.max(-1, ...(incoming.get(node) ?? []).map((p) => layer.get(p) ?? 0)) + 1;
    layer.set(node, here);
    for (const next of outgoing.get(node) ?? []) {
      const left = (waiting.get(next) ?? 0) - 1;
      waiting.set(next, left);
      if (left === 0) ready.push(next);
    }
  }
  return layer;
}

/** The order of the instances in each column: the input's order, then sorted by where their
 * neighbours in the other columns sit (barycentres, down then up, twice) to uncross arrows. */
function orderColumns(names: readonly string[], layer: Map<string, number>, edges: readonly Grouped[]): string[][] {
  const count = Math.max(0, ...layer.values()) + 1;
  const columns: string[][] = Array.from({ length: count }, () => []);
  for (const n of names) columns[layer.get(n) ?? 0]?.push(n);
  const position = new Map<string, number>();
  const place = () => columns.forEach((col) => col.forEach((n, i) => position.set(n, i)));
  place();
  const neighbours = (node: string, before: boolean) =>
    edges
      .filter((e) => e.from !== e.to)
      .flatMap((e) => (e.to === node ? [e.from] : e.from === node ? [e.to] : []))
      .filter((n) => (before ? (layer.get(n) ?? 0) < (layer.get(node) ?? 0) : (layer.get(n) ?? 0) > (layer.get(node) ?? 0)));
  const sweep = (order: number[], before: boolean) => {
    for (const c of order) {
      const col = columns[c] as string[];
      const key = new Map(
        col.map((n) => {
          const near = neighbours(n, before).map((m) => position.get(m) ?? 0);
          return [n, near.length ? near.reduce((a, b) => a + b, 0) / near.length : (position.get(n) ?? 0)];
        }),
      );
      // A stable sort: ties keep their order.
      col.sort((a, b) => (key.get(a) ?? 0) - (key.get(b) ?? 0));
      col.forEach((n, i) => position.set(n, i));
    }
  };
  const down = columns.map((_, i) => i).slice(1);
  const up = columns.map((_, i) => i).slice(0, -1).reverse();
  for (let pass = 0; pass < 2; pass++) {
    sweep(down, true);
    sweep(up, false);
  }
  return columns;
}

const textWidth = (text: string) => text.length * CHAR_W;

function labelText(labels: string[]): string {
  if (labels.length <= LABEL_MAX) return labels.join(", ");
  return `${labels.slice(0, LABEL_MAX).join(", ")} +${labels.length - LABEL_MAX}`;
}

/** The point at t = 0.5 of a cubic Bézier curve. */
function midpoint(p: number[][]): [number, number] {
  const [a, b, c, d] = p as [number[], number[], number[], number[]];
  return [((a[0] ?? 0) + 3 * (b[0] ?? 0) + 3 * (c[0] ?? 0) + (d[0] ?? 0)) / 8, ((a[1] ?? 0) + 3 * (b[1] ?? 0) + 3 * (c[1] ?? 0) + (d[1] ?? 0)) / 8];
}

function curve(p: number[][]): string {
  const [a, b, c, d] = p as [number[], number[], number[], number[]];
  return `M ${a[0]} ${a[1]} C ${b[0]} ${b[1]}, ${c[0]} ${c[1]}, ${d[0]} ${d[1]}`;
}

type Point = [number, number];

/** An orthogonal route through `points` (each turn rounded by a small quadratic corner). */
function route(points: Point[], r = CORNER): string {
  const [first, ...rest] = points as [Point, ...Point[]];
  const parts = [`M ${first[0]} ${first[1]}`];
  rest.forEach((p, i) => {
    const next = rest[i + 1];
    if (!next) {
      parts.push(`L ${p[0]} ${p[1]}`);
      return;
    }
    const prev = (i === 0 ? first : rest[i - 1]) as Point;
    const toward = (from: Point, to: Point, d: number): Point => {
      const len = Math.hypot(to[0] - from[0], to[1] - from[1]) || 1;
      const k = Math.min(d, len / 2) / len;
      return [from[0] + (to[0] - from[0]) * k, from[1] + (to[1] - from[1]) * k];
    };
    const [a, b] = [toward(p, prev, r), toward(p, next, r)];
    parts.push(`L ${a[0]} ${a[1]}`, `Q ${p[0]} ${p[1]}, ${b[0]} ${b[1]}`);
  });
  return parts.join(" ");
}

/** How an edge is drawn: a self loop; back (closing a cycle: right to left, below); over (a
 * forward edge that skips columns: above the boxes, so that it does not cross those between);
 * forward (to the next column, straight across). */
function kindOf(g: Grouped, layer: Map<string, number>, back: Set<string>): EdgeKind {
  if (g.from === g.to) return "self";
  if (back.has(edgeKey(g.from, g.to))) return "back";
  return (layer.get(g.to) ?? 0) - (layer.get(g.from) ?? 0) > 1 ? "over" : "forward";
}

/** A level (0 nearest the boxes) for each arc spanning columns [lo, hi], so that arcs on one
 * level never share a stretch of columns (they may meet at a column); shorter arcs inside. */
export function arcLevels(spans: readonly [number, number][]): number[] {
  const order = spans.map((_, i) => i).sort((i, j) => {
    const [a, b] = [spans[i] as [number, number], spans[j] as [number, number]];
    return a[1] - a[0] - (b[1] - b[0]) || a[0] - b[0];
  });
  const taken: [number, number][][] = [];
  const levels = new Array<number>(spans.length).fill(0);
  for (const i of order) {
    const [lo, hi] = spans[i] as [number, number];
    let level = 0;
    while ((taken[level] ?? []).some(([l, h]) => Math.max(l, lo) < Math.min(h, hi))) level++;
    (taken[level] ??= []).push([lo, hi]);
    levels[i] = level;
  }
  return levels;
}

/** An edge as the drawing needs it: its kind, the columns it spans, its arc's level. */
interface Planned extends Grouped {
  kind: EdgeKind;
  span: [number, number];
  level: number;
}

function planEdges(grouped: readonly Grouped[], layer: Map<string, number>, back: Set<string>): Planned[] {
  const planned = grouped.map((g) => {
    const [x, y] = [layer.get(g.from) ?? 0, layer.get(g.to) ?? 0];
    return { ...g, kind: kindOf(g, layer, back), span: [Math.min(x, y), Math.max(x, y)] as [number, number], level: 0 };
  });
  // Arcs above (over) and below (back) each get levels of their own.
  for (const kind of ["over", "back"] as const) {
    const arcs = planned.filter((e) => e.kind === kind);
    arcLevels(arcs.map((e) => e.span)).forEach((level, i) => ((arcs[i] as Planned).level = level));
  }
  return planned;
}

/** Each column's boxes one under another, centred on the tallest column, from `top`; each
 * column as wide as its widest box, the gap after it wide enough for its arrows' labels.
 * Answers the boxes and the right edge of the last column. */
function placeBoxes(columns: string[][], edges: readonly Planned[], top: number, loopInstances: Set<string>): { boxes: Map<string, Box>; right: number } {
  const boxWidth = (n: string) => Math.max(BOX_MIN_W, textWidth(n) + BOX_PAD);
  const colWidth = columns.map((col) => Math.max(BOX_MIN_W, ...col.map(boxWidth)));
  const gapAfter = columns.map((_, c) =>
    Math.max(COL_GAP_MIN, ...edges.filter((e) => (e.kind === "forward" || e.kind === "back") && e.span[0] === c && e.span[1] === c + 1).map((e) => textWidth(labelText(e.labels)) + 30)),
  );
  const tallest = Math.max(1, ...columns.map((col) => col.length));
  const boxes = new Map<string, Box>();
  let x = MARGIN;
  columns.forEach((col, c) => {
    const y0 = top + ((tallest - col.length) * (BOX_H + ROW_GAP)) / 2;
    col.forEach((name, i) => {
      const width = boxWidth(name);
      const y = y0 + i * (BOX_H + ROW_GAP);
      boxes.set(name, { name, layer: c, x: x + ((colWidth[c] ?? width) - width) / 2, y, width, height: BOX_H, inLoop: loopInstances.has(name) });
    });
    x += (colWidth[c] ?? 0) + (c < columns.length - 1 ? (gapAfter[c] ?? COL_GAP_MIN) : 0);
  });
  return { boxes, right: x };
}

interface Shape {
  path: string;
  labelX: number;
  labelY: number;
}

/** An edge's path and where its label goes. Arrows between neighbouring columns stay in the
 * gap between them (no box is there): forward straight across, back as a U below. Longer arcs
 * run in the gaps beside their ends and above (over) or below (back) every box of the columns
 * they span (`inSpan`), so that none crosses a box. */
function edgeShape(e: Planned, a: Box, b: Box, inSpan: Box[]): Shape {
  const [ya, yb] = [a.y + a.height / 2, b.y + b.height / 2];
  if (e.kind === "self") {
    const right = a.x + a.width;
    const points = [[right - 18, a.y], [right - 18, a.y - SELF_RISE], [right + 26, a.y - SELF_RISE], [right, a.y + 10]];
    return { path: curve(points), labelX: midpoint(points)[0], labelY: a.y - SELF_RISE - 4 };
  }
  if (e.kind === "forward") {
    const [x1, x2] = [a.x + a.width, b.x];
    const pull = Math.max(30, (x2 - x1) / 2);
    const points = [[x1, ya], [x1 + pull, ya], [x2 - pull, yb], [x2, yb]];
    const [labelX, labelY] = midpoint(points);
    return { path: curve(points), labelX, labelY: labelY - 8 };
  }
  const step = ARC_STEP * e.level;
  if (e.kind === "back") {
    // Out of the left side and into the right one, below the middle where forward arrows are.
    const [x1, x2] = [a.x, b.x + b.width];
    const [out, into] = [ya + BACK_DROP, yb + BACK_DROP];
    const adjacent = e.span[1] - e.span[0] === 1;
    const bottom = adjacent ? Math.max(out, into) + ARC_DEPTH + step : Math.max(...inSpan.map((c) => c.y + c.height)) + ARC_DEPTH + step;
    const lead = LEAD_BACK + LANE * e.level;
    const [gapA, gapB] = [x1 - lead, x2 + lead];
    const path = route([[x1, out], [gapA, out], [gapA, bottom], [gapB, bottom], [gapB, into], [x2, into]]);
    return { path, labelX: (gapA + gapB) / 2, labelY: bottom };
  }
  // over: out of the right side and into the left one, above every box between.
  const [x1, x2] = [a.x + a.width, b.x];
  const peak = Math.min(...inSpan.map((c) => c.y)) - ARC_DEPTH - step;
  const lead = LEAD_OVER + LANE * e.level;
  const [gapA, gapB] = [x1 + lead, x2 - lead];
  const path = route([[x1, ya - OVER_RISE], [gapA, ya - OVER_RISE], [gapA, peak], [gapB, peak], [gapB, yb - OVER_RISE], [x2, yb - OVER_RISE]]);
  return { path, labelX: (gapA + gapB) / 2, labelY: peak };
}

/** The whole drawing: boxes placed, every edge's path and label, and the size of it all. */
export function layoutGraph(input: GraphInput): Layout {
  const names = [...new Set([...input.instances])];
  const grouped = groupConnections(input, names);
  // An instance named only by a connection (not in the list) still gets its box.
  for (const e of grouped) for (const n of [e.from, e.to]) if (!names.includes(n)) names.push(n);
  const back = backEdges(names, grouped);
  const layer = layers(names, grouped.filter((e) => e.from !== e.to && !back.has(edgeKey(e.from, e.to))));
  const columns = orderColumns(names, layer, grouped);
  const planned = planEdges(grouped, layer, back);
  const loopInstances = new Set(input.loops.flat().map((p) => splitPort(p, names).instance));

  // Room above the boxes for self loops and the arcs over them.
  const overLevels = Math.max(0, ...planned.filter((e) => e.kind === "over").map((e) => e.level + 1));
  const selfRoom = planned.some((e) => e.kind === "self") ? SELF_RISE + 14 : 0;
  const overRoom = overLevels ? ARC_DEPTH + ARC_STEP * (overLevels - 1) + 12 : 0;
  const top = MARGIN + Math.max(selfRoom, overRoom);
  const { boxes, right } = placeBoxes(columns, planned, top, loopInstances);
  const tallest = Math.max(1, ...columns.map((col) => col.length));
  let width = right + MARGIN;
  let height = top + tallest * BOX_H + (tallest - 1) * ROW_GAP + MARGIN;

  const edges = planned.map((e): Edge => {
    const a = boxes.get(e.from) as Box;
    const b = boxes.get(e.to) as Box;
    const [lo, hi] = e.span;
    const { path, labelX, labelY } = edgeShape(e, a, b, [...boxes.values()].filter((c) => c.layer >= lo && c.layer <= hi));
    const text = labelText(e.labels);
    const labelWidth = textWidth(text) + 8;
    width = Math.max(width, labelX + labelWidth / 2 + MARGIN);
    height = Math.max(height, labelY + MARGIN);
    return { from: e.from, to: e.to, labels: e.labels, text, kind: e.kind, inLoop: e.inLoop, path, labelX, labelY, labelWidth };
  });
  return { width, height, boxes: [...boxes.values()], edges };
}
