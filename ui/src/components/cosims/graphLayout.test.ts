import { describe, expect, it } from "vitest";
import type { CosimConnection } from "../../api/cosims";
import { arcLevels, backEdges, BOX_H, layers, layoutGraph, splitPort, type Box, type Layout } from "./graphLayout";

const conn = (source: string, target: string): CosimConnection => ({ source, target });
const box = (layout: Layout, name: string) => layout.boxes.find((b) => b.name === name) as Box;
const edge = (layout: Layout, from: string, to: string) => layout.edges.find((e) => e.from === from && e.to === to);

/** Every number of an SVG path, as [x, y] pairs. */
function pathPoints(path: string): [number, number][] {
  const n = (path.match(/-?\d+(\.\d+)?/g) ?? []).map(Number);
  return Array.from({ length: n.length / 2 }, (_, i) => [n[2 * i] as number, n[2 * i + 1] as number]);
}

/** Whether an arc (an orthogonal route: its points are its corners and the ends of their
 * rounding) goes through any box. */
function crossesABox(layout: Layout, path: string): boolean {
  const points = pathPoints(path);
  return points.slice(1).some((q, i) => {
    const p = points[i] as [number, number];
    const [x0, x1, y0, y1] = [Math.min(p[0], q[0]), Math.max(p[0], q[0]), Math.min(p[1], q[1]), Math.max(p[1], q[1])];
    return layout.boxes.some((b) => x1 > b.x + 0.5 && x0 < b.x + b.width - 0.5 && y1 > b.y + 0.5 && y0 < b.y + b.height - 0.5);
  });
}

function overlaps(a: Box, b: Box): boolean {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

// The INTO-CPS mass-spring-damper as Maestro names it: instances with dots in their names.
const MSD = {
  instances: ["msd1.m1", "msd2.m2"],
  connections: [conn("msd1.m1.x1", "msd2.m2.x1"), conn("msd1.m1.v1", "msd2.m2.v1"), conn("msd2.m2.fk", "msd1.m1.fk")],
  loops: [],
};

describe("splitPort", () => {
  it("takes the longest instance name before a dot, so instance names may hold dots", () => {
    expect(splitPort("msd1.m1.x1", ["msd1", "msd1.m1"])).toEqual({ instance: "msd1.m1", variable: "x1" });
    expect(splitPort("plant.T.body", ["plant"])).toEqual({ instance: "plant", variable: "T.body" });
  });

  it("splits an unknown instance at the last dot", () => {
    expect(splitPort("a.b.y", [])).toEqual({ instance: "a.b", variable: "y" });
  });
});

describe("layoutGraph", () => {
  it("draws a coupled pair left to right, the arrow back below the boxes", () => {
    const layout = layoutGraph(MSD);
    const [mass, spring] = [box(layout, "msd1.m1"), box(layout, "msd2.m2")];
    expect([mass.layer, spring.layer]).toEqual([0, 1]);
    expect(mass.x + mass.width).toBeLessThan(spring.x);
    const forward = edge(layout, "msd1.m1", "msd2.m2");
    expect(forward).toMatchObject({ kind: "forward", labels: ["x1", "v1"], text: "x1, v1", inLoop: false });
    const back = edge(layout, "msd2.m2", "msd1.m1");
    expect(back).toMatchObject({ kind: "back", labels: ["fk"], inLoop: false });
    // Out of the spring's left side, a U below the forward arrow in the gap between them,
    // into the mass's right side; through no box.
    const points = pathPoints(back!.path);
    const middle = mass.y + mass.height / 2;
    expect(points[0]).toEqual([spring.x, middle + 8]);
    expect(points.at(-1)).toEqual([mass.x + mass.width, middle + 8]);
    const lowest = Math.max(...points.map((p) => p[1]));
    expect(lowest).toBeGreaterThan(middle + 8);
    expect(points.every((p) => p[0] >= mass.x + mass.width && p[0] <= spring.x)).toBe(true);
    expect(crossesABox(layout, back!.path)).toBe(false);
    expect(layout.height).toBeGreaterThan(lowest);
    // The forward arrow leaves the mass's right side and ends on the spring's left side.
    const fwd = pathPoints(forward!.path);
    expect(fwd[0]![0]).toBe(mass.x + mass.width);
    expect(fwd[3]![0]).toBe(spring.x);
    expect(layout.boxes.every((b) => !b.inLoop)).toBe(true);
  });

  it("marks the connections and instances of an algebraic loop, and only those", () => {
    const layout = layoutGraph({
      instances: ["a", "b", "c"],
      connections: [conn("a.y", "b.u"), conn("b.y", "a.u"), conn("b.z", "c.u"), conn("a.w", "b.w")],
      loops: [["a.y", "b.u", "b.y", "a.u"]],
    });
    expect(edge(layout, "a", "b")).toMatchObject({ inLoop: true, labels: ["y → u", "w"] });
    expect(edge(layout, "b", "a")).toMatchObject({ inLoop: true, kind: "back" });
    expect(edge(layout, "b", "c")).toMatchObject({ inLoop: false, kind: "forward" });
    expect(layout.boxes.filter((b) => b.inLoop).map((b) => b.name)).toEqual(["a", "b"]);
  });

  it("layers by the longest path, boxes of one column one under another", () => {
    const layout = layoutGraph({
      instances: ["d", "c", "b", "a"],
      connections: [conn("a.y", "b.u"), conn("a.y", "c.u"), conn("b.y", "d.u"), conn("c.y", "d.v"), conn("a.z", "d.w")],
      loops: [],
    });
    expect(Object.fromEntries(layout.boxes.map((b) => [b.name, b.layer]))).toEqual({ a: 0, b: 1, c: 1, d: 2 });
    const [b, c] = [box(layout, "b"), box(layout, "c")];
    expect(b.x).toBe(c.x);
    for (const one of layout.boxes) {
      for (const other of layout.boxes) if (one !== other) expect(overlaps(one, other)).toBe(false);
    }
    // a -> d skips a column: drawn over the boxes, not through b or c.
    expect(layout.edges.filter((e) => e.kind !== "forward").map((e) => `${e.from}>${e.to}:${e.kind}`)).toEqual(["a>d:over"]);
    const over = edge(layout, "a", "d")!;
    const peak = Math.min(...pathPoints(over.path).map((p) => p[1]));
    expect(peak).toBeLessThan(Math.min(...layout.boxes.map((x) => x.y)));
    expect(peak).toBeGreaterThan(0);
    expect(crossesABox(layout, over.path)).toBe(false);
    expect(layout.width).toBeGreaterThan(Math.max(...layout.boxes.map((x) => x.x + x.width)));
  });

  it("routes arcs around the boxes of columns that hold several", () => {
    // b and e share a column: arrows back out of b and into it, and arcs over from e, pass
    // through neither.
    const layout = layoutGraph({
      instances: ["a", "b", "c", "d", "e"],
      connections: [
        conn("a.y", "b.u"), conn("b.y", "a.u"), conn("b.z", "c.u"), conn("a.w", "d.w"), conn("c.y", "d.v"),
        conn("a.q", "e.q"), conn("e.r", "d.r"), conn("d.back", "b.back"),
      ],
      loops: [],
    });
    expect(box(layout, "b").layer).toBe(box(layout, "e").layer);
    const arcs = layout.edges.filter((e) => e.kind === "back" || e.kind === "over");
    expect(arcs.map((e) => `${e.from}>${e.to}`).sort()).toEqual(["a>d", "b>a", "d>b", "e>d"]);
    for (const arc of arcs) expect(crossesABox(layout, arc.path), `${arc.from} > ${arc.to}`).toBe(false);
  });

  it("orders a column by where its feeders sit, so arrows do not cross", () => {
    const layout = layoutGraph({
      instances: ["a1", "a2", "b1", "b2"],
      connections: [conn("a1.y", "b2.u"), conn("a2.y", "b1.u")],
      loops: [],
    });
    expect(box(layout, "a1").y).toBeLessThan(box(layout, "a2").y);
    expect(box(layout, "b2").y).toBeLessThan(box(layout, "b1").y);
  });

  it("draws an instance feeding itself as a loop over its box, with room above", () => {
    const layout = layoutGraph({ instances: ["pid"], connections: [conn("pid.y", "pid.y_prev")], loops: [] });
    const self = edge(layout, "pid", "pid");
    expect(self).toMatchObject({ kind: "self", labels: ["y → y_prev"] });
    expect(self!.labelY).toBeGreaterThan(0);
    expect(box(layout, "pid").y).toBeGreaterThan(self!.labelY);
  });

  it("writes the first three variables of a wide connection and counts the rest", () => {
    const names = ["p", "q", "r", "s", "t"];
    const layout = layoutGraph({ instances: ["x", "y"], connections: names.map((n) => conn(`x.${n}`, `y.${n}`)), loops: [] });
    const e = edge(layout, "x", "y")!;
    expect(e.text).toBe("p, q, r +2");
    expect(e.labels).toEqual(names);
  });

  it("gives a box to an instance only a connection names, and lays out a long chain in a row", () => {
    const chain = Array.from({ length: 10 }, (_, i) => `m${i}`);
    const connections = chain.slice(1).flatMap((n, i) => [conn(`${chain[i]}.x`, `${n}.x_in`), conn(`${n}.f`, `${chain[i]}.f_in`)]);
    const layout = layoutGraph({ instances: chain.slice(0, 9), connections, loops: [] });
    expect(layout.boxes.map((b) => b.layer)).toEqual(chain.map((_, i) => i));
    const backs = layout.edges.filter((e) => e.kind === "back");
    expect(backs).toHaveLength(9);
    // Neighbours' arrows back share no stretch: one depth for all, just below the row.
    const depths = backs.map((e) => Math.max(...pathPoints(e.path).map((p) => p[1])));
    expect(new Set(depths).size).toBe(1);
    expect(layout.height).toBeLessThan(box(layout, "m0").y + BOX_H + 100);
    // At each box the arrow in and the arrow out do not meet in one point.
    for (const name of chain.slice(1, -1)) {
      const arriving = pathPoints(backs.find((e) => e.to === name)!.path).at(-1)!;
      const leaving = pathPoints(backs.find((e) => e.from === name)!.path)[0]!;
      expect(arriving[0]).not.toBe(leaving[0]);
    }
  });
});

describe("arcLevels", () => {
  it("puts arcs that share a stretch of columns on different levels, the shorter inside", () => {
    expect(arcLevels([[0, 3], [1, 2], [0, 1], [1, 2]])).toEqual([2, 0, 0, 1]);
    // Meeting at a column is no overlap.
    expect(arcLevels([[0, 1], [1, 2], [2, 3]])).toEqual([0, 0, 0]);
  });
});

describe("backEdges and layers", () => {
  it("breaks every cycle once, so that the rest is layered", () => {
    const names = ["a", "b", "c"];
    const edges = [
      { from: "a", to: "b" },
      { from: "b", to: "c" },
      { from: "c", to: "a" },
      { from: "c", to: "b" },
    ];
    const back = backEdges(names, edges);
    expect([...back].map((k) => k.replace("\u0000", ">")).sort()).toEqual(["c>a", "c>b"]);
    const forward = edges.filter((e) => !back.has(`${e.from}\u0000${e.to}`));
    expect(Object.fromEntries(layers(names, forward))).toEqual({ a: 0, b: 1, c: 2 });
  });
});
