// The one place that knows uPlot: a time chart (x = seconds since the epoch) of several series.
// Data comes either as a prop (history) or through the handle passed to `onReady` (live data,
// set once per animation frame without going through React). Every series is drawn as steps
// and held stretches dashed (steps.ts); times are in the user's locale.
import { useEffect, useRef } from "react";
import type uPlot from "uplot";
import "uplot/dist/uPlot.min.css";
import "./charts.css";
import { chartOptions, type ChartCallbacks, type ChartSeries } from "./chartOptions";
import type { ChartFrame, Held } from "./steps";

export type { ChartSeries } from "./chartOptions";

export interface TimeChartHandle {
  /** Show `frame`; with `xRange` the x axis spans exactly that, else the data. */
  setData: (frame: ChartFrame, xRange?: [number, number]) => void;
  /** The plot's width in CSS pixels: how many columns are worth drawing. */
  columns: () => number;
}

export interface TimeChartProps {
  series: ChartSeries[];
  /** What the chart shows, for assistive technology. */
  label: string;
  frame?: ChartFrame;
  /** What the x axis spans with `frame` (else the data). */
  xRange?: [number, number];
  height?: number;
  onReady?: (handle: TimeChartHandle | null) => void;
  /** A range was selected by dragging over the chart (seconds). */
  onZoom?: (range: [number, number]) => void;
  /** The chart was double-clicked. */
  onResetZoom?: () => void;
}

let uplotClass: Promise<typeof uPlot> | null = null;

/** uPlot, loaded once on first use: pages without charts do not pay for it. */
function loadUplot(): Promise<typeof uPlot> {
  uplotClass ??= import("uplot").then((module) => module.default);
  return uplotClass;
}

export function TimeChart({ series, label, frame, xRange, height = 320, onReady, onZoom, onResetZoom }: TimeChartProps) {
  const box = useRef<HTMLDivElement>(null);
  const chart = useRef<Drawn | null>(null);
  const callbacks = useRef<ChartCallbacks>({});
  callbacks.current = { onZoom, onResetZoom };
  const latest = useRef({ frame, xRange, onReady });
  latest.current = { frame, xRange, onReady };
  const seriesKey = series.map((s) => `${s.label}@${s.scale ?? "y"}@${s.unit ?? ""}`).join("\n");

  useEffect(() => {
    const el = box.current;
    if (!el) return;
    let cleanup: (() => void) | null = null;
    let cancelled = false;
    void loadUplot().then((UPlot) => {
      if (cancelled) return;
      const held = { current: [] as Held[] };
      const size = { width: Math.max(200, el.clientWidth || 800), height };
      const u = new UPlot(chartOptions(UPlot, series, size, callbacks, held), emptyFrame(series.length).data, el);
      const drawn: Drawn = { u, held };
      const { frame: first, xRange: range } = latest.current;
      show(drawn, first ?? emptyFrame(series.length), range);
      cleanup = mount(drawn, el, height, chart, latest.current.onReady);
    });
    return () => {
      cancelled = true;
      cleanup?.();
    };
    // The chart is made again only when its series or height change.
    // eslint-disable-next-line react-hooks/exhaustive-deps
  }, [seriesKey, height]);

  const rangeKey = xRange?.join(",");
  useEffect(() => {
    if (frame && chart.current) show(chart.current, frame, latest.current.xRange);
  }, [frame, rangeKey]);

  return <div className="time-chart" ref={box} role="figure" aria-label={label} />;
}

/** A chart and the held stretches its draw hook reads. */
interface Drawn {
  u: uPlot;
  held: { current: Held[] };
}

function emptyFrame(count: number): ChartFrame {
  return { data: [[], ...Array.from({ length: count }, () => [])], held: [] };
}

function show({ u, held }: Drawn, frame: ChartFrame, range: [number, number] | undefined): void {
  held.current = frame.held;
  u.batch(() => {
    u.setData(frame.data, !range);
    if (range) u.setScale("x", { min: range[0], max: range[1] });
  });
}

/** Follow the box's width, hand out the handle; answers what undoes it all. */
function mount(
  drawn: Drawn,
  el: HTMLElement,
  height: number,
  chart: { current: Drawn | null },
  onReady: ((handle: TimeChartHandle | null) => void) | undefined,
): () => void {
  const { u } = drawn;
  chart.current = drawn;
  const observer = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(() => {
    const w = el.clientWidth;
    if (w > 0 && Math.abs(w - u.width) > 1) u.setSize({ width: w, height });
  });
  observer?.observe(el);
  const handle: TimeChartHandle = {
    setData: (frame, range) => show(drawn, frame, range),
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
