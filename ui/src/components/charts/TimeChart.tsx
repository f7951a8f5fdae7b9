// The one place that knows uPlot: a time chart (x = seconds since the epoch) of several series.
// Data comes either as a prop (history) or through the handle passed to `onReady` (live data,
// set once per animation frame without going through React).
import { useEffect, useRef } from "react";
import type uPlot from "uplot";
import "uplot/dist/uPlot.min.css";
import "./charts.css";
import type { AlignedSeries } from "../../live/decimate";
import { meanStep, realGaps } from "./gaps";

export interface ChartSeries {
  label: string;
  /** "y2" puts the series on a second axis on the right. */
  scale?: "y" | "y2";
}

export interface TimeChartHandle {
  /** Show `data`; with `xRange` the x axis spans exactly that, else the data. */
  setData: (data: AlignedSeries, xRange?: [number, number]) => void;
  /** The plot's width in CSS pixels: how many columns are worth drawing. */
  columns: () => number;
}

export interface TimeChartProps {
  series: ChartSeries[];
  /** What the chart shows, for assistive technology. */
  label: string;
  data?: AlignedSeries;
  height?: number;
  onReady?: (handle: TimeChartHandle | null) => void;
  /** A range was selected by dragging over the chart (seconds). */
  onZoom?: (range: [number, number]) => void;
  /** The chart was double-clicked. */
  onResetZoom?: () => void;
}

export const PALETTE = ["#1f5fbf", "#d95f02", "#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#a6761d", "#555"];

interface Callbacks {
  onZoom?: (range: [number, number]) => void;
  onResetZoom?: () => void;
}

/** Break a line only where it has no values for much longer than its usual step. */
function refineGaps(u: uPlot, seriesIdx: number, idx0: number, idx1: number, gaps: uPlot.Series.Gaps): uPlot.Series.Gaps {
  const xs = u.data[0];
  const { min, max } = u.scales.x ?? {};
  if (gaps.length === 0 || min === undefined || max === undefined || max <= min) return gaps;
  const step = meanStep(xs, u.data[seriesIdx] as ArrayLike<number | null>, idx0, idx1);
  return realGaps(gaps as [number, number][], step, u.bbox.width / (max - min));
}

/** Wide enough for the longest tick label (about 7 px a character at the chart's font). */
function axisSize(_u: uPlot, values: string[] | null): number {
  const longest = (values ?? []).reduce((n, v) => Math.max(n, v.length), 0);
  return Math.max(40, 18 + 7 * longest);
}

function chartOptions(series: ChartSeries[], width: number, height: number, callbacks: { current: Callbacks }): uPlot.Options {
  const hasY2 = series.some((s) => s.scale === "y2");
  const axes: uPlot.Axis[] = [{}, { scale: "y", size: axisSize }];
  if (hasY2) axes.push({ scale: "y2", side: 1, size: axisSize, grid: { show: false }, stroke: PALETTE[series.findIndex((s) => s.scale === "y2") % PALETTE.length] });
  return {
    width,
    height,
    series: [
      {},
      ...series.map((s, i) => ({
        label: s.label,
        scale: s.scale ?? "y",
        stroke: PALETTE[i % PALETTE.length],
        width: 1.25,
        spanGaps: false,
        gaps: refineGaps,
      })),
    ],
    scales: { x: { time: true } },
    axes,
    // Dragging selects a range that the page decides what to do with (zoom, or fetch it).
    cursor: {
      drag: { x: true, y: false, setScale: false },
      bind: { dblclick: () => () => (callbacks.current.onResetZoom?.(), null) },
    },
    hooks: {
      setSelect: [
        (u) => {
          const { left, width: w } = u.select;
          if (w > 2) callbacks.current.onZoom?.([u.posToVal(left, "x"), u.posToVal(left + w, "x")]);
          u.setSelect({ left: 0, top: 0, width: 0, height: 0 }, false);
        },
      ],
    },
  };
}

let uplotClass: Promise<typeof uPlot> | null = null;

/** uPlot, loaded once on first use: pages without charts do not pay for it. */
function loadUplot(): Promise<typeof uPlot> {
  uplotClass ??= import("uplot").then((module) => module.default);
  return uplotClass;
}

function emptyData(count: number): AlignedSeries {
  return [[], ...Array.from({ length: count }, () => [])];
}

export function TimeChart({ series, label, data, height = 320, onReady, onZoom, onResetZoom }: TimeChartProps) {
  const box = useRef<HTMLDivElement>(null);
  const chart = useRef<uPlot | null>(null);
  const callbacks = useRef<Callbacks>({});
  callbacks.current = { onZoom, onResetZoom };
  const latest = useRef({ data, onReady });
  latest.current = { data, onReady };
  const seriesKey = series.map((s) => `${s.label}@${s.scale ?? "y"}`).join("\n");

  useEffect(() => {
    const el = box.current;
    if (!el) return;
    let cleanup: (() => void) | null = null;
    let cancelled = false;
    void loadUplot().then((UPlot) => {
      if (cancelled) return;
      const width = Math.max(200, el.clientWidth || 800);
      const u = new UPlot(chartOptions(series, width, height, callbacks), latest.current.data ?? emptyData(series.length), el);
      cleanup = mount(u, el, height, chart, latest.current.onReady);
    });
    return () => {
      cancelled = true;
      cleanup?.();
    };
    // The chart is made again only when its series or height change.
    // eslint-disable-next-line react-hooks/exhaustive-deps
  }, [seriesKey, height]);

  useEffect(() => {
    if (data && chart.current) chart.current.setData(data);
  }, [data]);

  return <div className="time-chart" ref={box} role="figure" aria-label={label} />;
}

/** Follow the box's width, hand out the handle; answers what undoes it all. */
function mount(
  u: uPlot,
  el: HTMLElement,
  height: number,
  chart: { current: uPlot | null },
  onReady: ((handle: TimeChartHandle | null) => void) | undefined,
): () => void {
  chart.current = u;
  const observer = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(() => {
    const w = el.clientWidth;
    if (w > 0 && Math.abs(w - u.width) > 1) u.setSize({ width: w, height });
  });
  observer?.observe(el);
  const handle: TimeChartHandle = {
    setData: (d, range) =>
      u.batch(() => {
        u.setData(d, !range);
        if (range) u.setScale("x", { min: range[0], max: range[1] });
      }),
    columns: () => Math.max(50, Math.round(u.bbox.width / (window.devicePixelRatio || 1)) || u.width),
  };
  onReady?.(handle);
  return () => {
    onReady?.(null);
    observer?.disconnect();
    u.destroy();
    chart.current = null;
  };
}
