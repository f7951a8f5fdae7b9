// A co-simulation's results as a uPlot chart: x the simulated time in seconds (not a wall
// clock, so not TimeChart's time axis), one line per recorded column ("instance.variable").
// The data is already decimated by the server (max_points); a new answer replaces it in place,
// the chart is made again only when the columns change.
import { useEffect, useRef } from "react";
import type uPlot from "uplot";
import "uplot/dist/uPlot.min.css";
import "../charts/charts.css";
import { PALETTE } from "../charts/chartOptions";
import type { CosimResults } from "../../api/cosims";

/** Columns drawn at first; the others are listed in the legend, a click there shows them. */
export const SHOWN_AT_FIRST = 8;
const numbers = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 6 });

let uplotClass: Promise<typeof uPlot> | null = null;

function loadUplot(): Promise<typeof uPlot> {
  uplotClass ??= import("uplot").then((module) => module.default);
  return uplotClass;
}

/** Whether the x axis shows less than the whole of the data: the user zoomed in. */
export function isZoomed(u: Pick<uPlot, "scales" | "data">): boolean {
  const times = u.data[0] ?? [];
  const [first, last] = [times[0], times[times.length - 1]];
  const { min, max } = u.scales.x ?? {};
  if (first == null || last == null || min == null || max == null) return false;
  const slack = (last - first) * 1e-9;
  return min > first + slack || max < last - slack;
}

export function resultOptions(
  columns: string[],
  size: { width: number; height: number },
  zoomed: { current: boolean } = { current: false },
): uPlot.Options {
  return {
    ...size,
    series: [
      { label: "time (s)", value: (_u, v) => (v === null ? "" : `${numbers.format(v)} s`) },
      ...columns.slice(1).map((label, i) => ({
        label,
        stroke: PALETTE[i % PALETTE.length],
        width: 1.25,
        show: i < SHOWN_AT_FIRST,
        points: { show: false },
        value: (_u: uPlot, v: number | null) => (v === null ? "" : numbers.format(v)),
      })),
    ],
    scales: { x: { time: false } },
    axes: [{ label: "simulated time (s)", labelSize: 20 }, { size: 60 }],
    cursor: { drag: { x: true, y: false } },
    // Dragging zooms in, a double-click zooms out (uPlot's own); new data while it runs then
    // keeps the zoom the user chose instead of jumping back to the whole run.
    hooks: { setScale: [(u, key) => void (key === "x" && (zoomed.current = isZoomed(u)))] },
  };
}

interface Props {
  results: CosimResults;
  height?: number;
}

export function ResultsChart({ results, height = 320 }: Props) {
  const box = useRef<HTMLDivElement>(null);
  const chart = useRef<uPlot | null>(null);
  const zoomed = useRef(false);
  const latest = useRef(results);
  latest.current = results;
  const columnsKey = results.columns.join("\n");

  useEffect(() => {
    const el = box.current;
    if (!el) return;
    let cancelled = false;
    let observer: ResizeObserver | null = null;
    void loadUplot().then((UPlot) => {
      if (cancelled) return;
      const size = { width: Math.max(200, el.clientWidth || 800), height };
      zoomed.current = false;
      const u = new UPlot(resultOptions(latest.current.columns, size, zoomed), latest.current.data as uPlot.AlignedData, el);
      chart.current = u;
      observer = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(() => {
        const w = el.clientWidth;
        if (w > 0 && Math.abs(w - u.width) > 1) u.setSize({ width: w, height });
      });
      observer?.observe(el);
    });
    return () => {
      cancelled = true;
      observer?.disconnect();
      chart.current?.destroy();
      chart.current = null;
    };
  }, [columnsKey, height]);

  useEffect(() => {
    chart.current?.setData(results.data as uPlot.AlignedData, !zoomed.current);
  }, [results]);

  const points = results.data[0]?.length ?? 0;
  return (
    <div
      className="time-chart cosim-chart"
      ref={box}
      role="figure"
      aria-label={`Results: ${results.columns.length - 1} columns, ${points} points`}
      data-points={points}
    />
  );
}
