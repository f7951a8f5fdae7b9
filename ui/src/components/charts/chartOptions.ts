// uPlot's options for a time chart: series drawn as steps (steps.ts), their held stretches
// dashed over them, the time axis and legend in the user's locale, and each y axis labelled
// with the units of its series.
import type uPlot from "uplot";
import { formatInstant, timeAxisValues } from "../common/time";
import type { Held } from "./steps";

export interface ChartSeries {
  label: string;
  /** "y2" puts the series on a second axis on the right. */
  scale?: "y" | "y2";
  /** The unit of its values (from the twin's interface), on its axis and in the legend. */
  unit?: string;
}

export interface ChartCallbacks {
  onZoom?: (range: [number, number]) => void;
  onResetZoom?: () => void;
}

export const PALETTE = ["#1f5fbf", "#d95f02", "#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#a6761d", "#555"];
const LINE_WIDTH = 1.25;
/** Dash and gap of a held stretch, in CSS pixels. */
const HELD_DASH = [5, 4];

const numbers = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 6 });

/** Wide enough for the longest tick label (about 7 px a character at the chart's font). */
function axisSize(_u: uPlot, values: string[] | null): number {
  const longest = (values ?? []).reduce((n, v) => Math.max(n, v.length), 0);
  return Math.max(40, 18 + 7 * longest);
}

/** The units of the series on `scale`, each once ("rad", "N, rad"); undefined when none. */
export function axisUnits(series: ChartSeries[], scale: "y" | "y2"): string | undefined {
  const units = [...new Set(series.filter((s) => (s.scale ?? "y") === scale && s.unit).map((s) => s.unit as string))];
  return units.length ? units.join(", ") : undefined;
}

function yAxis(series: ChartSeries[], scale: "y" | "y2"): uPlot.Axis {
  const unit = axisUnits(series, scale);
  const axis: uPlot.Axis = { scale, size: axisSize };
  if (unit) Object.assign(axis, { label: unit, labelSize: 20, labelFont: "600 12px system-ui, sans-serif" });
  if (scale === "y2") {
    Object.assign(axis, { side: 1, grid: { show: false }, stroke: PALETTE[series.findIndex((s) => s.scale === "y2") % PALETTE.length] });
  }
  return axis;
}

/** Draw the held stretches dashed, in their series' colours, over the solid steps. */
export function drawHeld(u: uPlot, held: Held[]): void {
  if (held.length === 0) return;
  const ctx = u.ctx;
  const ratio = typeof window === "undefined" ? 1 : window.devicePixelRatio || 1;
  const { left, top, width, height } = u.bbox;
  ctx.save();
  ctx.beginPath();
  ctx.rect(left, top, width, height);
  ctx.clip();
  ctx.lineWidth = LINE_WIDTH * ratio;
  ctx.setLineDash(HELD_DASH.map((n) => n * ratio));
  for (const h of held) {
    const s = u.series[h.series + 1];
    if (!s || s.show === false || !s.scale) continue;
    const y = u.valToPos(h.value, s.scale, true);
    ctx.strokeStyle = PALETTE[h.series % PALETTE.length] as string;
    ctx.beginPath();
    ctx.moveTo(u.valToPos(h.from, "x", true), y);
    ctx.lineTo(u.valToPos(h.to, "x", true), y);
    ctx.stroke();
  }
  ctx.restore();
}

export function chartOptions(
  UPlot: typeof uPlot,
  series: ChartSeries[],
  size: { width: number; height: number },
  callbacks: { current: ChartCallbacks },
  held: { current: Held[] },
): uPlot.Options {
  // Ticks far enough apart for the longest time label ("10:00:01.500 AM").
  const xAxis: uPlot.Axis = { space: 110, values: (_u, splits, _i, _space, incr) => timeAxisValues(splits, incr) };
  const axes: uPlot.Axis[] = [xAxis, yAxis(series, "y")];
  if (series.some((s) => s.scale === "y2")) axes.push(yAxis(series, "y2"));
  // uPlot.paths is optional in its types; the real class always has it.
  const steps = UPlot.paths.stepped?.({ align: 1 });
  return {
    ...size,
    series: [
      { value: (_u, v) => (v === null ? "" : formatInstant(v)) },
      ...series.map((s, i) => ({
        label: s.label,
        scale: s.scale ?? "y",
        stroke: PALETTE[i % PALETTE.length],
        width: LINE_WIDTH,
        // A null is where a held stretch takes over (drawn by drawHeld); undefined is spanned.
        spanGaps: false,
        paths: steps,
        points: { show: false },
        value: (_u: uPlot, v: number | null) => (v === null ? "" : s.unit ? `${numbers.format(v)} ${s.unit}` : numbers.format(v)),
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
      draw: [(u) => drawHeld(u, held.current)],
    },
  };
}
