// The live chart: draws the store at most once per animation frame, never per message.
// Following, the x axis ends at the server's "now" and spans the window; zoomed, it shows the
// chosen range. Paused, the picture stands still.
import { useEffect, useRef, useState } from "react";
import type { LiveStore } from "../../live/liveStore";
import { assignScales, magnitude, type ScaleKey } from "./scales";
import { stepFrame } from "./steps";
import { TimeChart, type TimeChartHandle } from "./TimeChart";

export interface LiveChartProps {
  store: LiveStore;
  windowS: number;
  paused: boolean;
  /** A range chosen by dragging; null follows live. */
  zoom: [number, number] | null;
  onZoom: (range: [number, number]) => void;
  onFollow: () => void;
  serverNow: () => number;
  /** Hands out the chart's width in columns, for the history backfill. */
  onColumns?: (columns: () => number) => void;
  /** Each chosen signal's unit, if known. */
  units?: (string | undefined)[];
}

/** A zoomed view only changes when data arrives; it need not be drawn more often than this. */
const ZOOMED_REDRAW_MS = 250;
/** How often to check whether the series need a second y axis (that makes a new chart). */
const SCALES_CHECK_MS = 1000;

export function LiveChart({ store, windowS, paused, zoom, onZoom, onFollow, serverNow, onColumns, units = [] }: LiveChartProps) {
  const [handle, setHandle] = useState<TimeChartHandle | null>(null);
  const shown = useRef<[number, number] | null>(null);
  const [scales, setScales] = useState<ScaleKey[]>([]);
  const scalesKey = scales.join(",");

  useEffect(() => {
    if (handle) onColumns?.(handle.columns);
  }, [handle, onColumns]);

  useEffect(() => {
    if (!handle) return;
    let frame = 0;
    let drawnVersion = -1;
    let drawnAt = 0;
    let scalesCheckedAt = 0;
    // Paused, the window stands still where it was.
    const frozenEnd = paused ? (shown.current?.[1] ?? serverNow()) : null;
    const draw = (now: number) => {
      frame = requestAnimationFrame(draw);
      const columns = handle.columns();
      const range: [number, number] = zoom ?? (frozenEnd !== null ? [frozenEnd - windowS, frozenEnd] : followRange(store, windowS, serverNow));
      const moved = !shown.current || range[0] !== shown.current[0] || range[1] !== shown.current[1];
      if (!moved && drawnVersion === store.version) return;
      // Drawing again before the window has moved by a pixel column changes nothing visible.
      const minInterval = zoom ? ZOOMED_REDRAW_MS : (windowS * 1000) / columns;
      if (drawnVersion !== -1 && now - drawnAt < minInterval) return;
      const data = zoom ? store.frame(range[0], range[1], columns) : store.followFrame(range[1], windowS, columns);
      // Each signal's last value holds to the end of the window: one sent on change shows
      // while it keeps its value, from before the window if need be.
      const steps = stepFrame(data, { start: range[0], end: range[1], before: store.before(range[0]) });
      handle.setData(steps, range);
      if (now - scalesCheckedAt > SCALES_CHECK_MS) {
        scalesCheckedAt = now;
        const next = assignScales(steps.data.slice(1).map((y) => magnitude(y)));
        if (next.join(",") !== scalesKey) setScales(next);
      }
      shown.current = range;
      drawnVersion = store.version;
      drawnAt = now;
    };
    frame = requestAnimationFrame(draw);
    return () => cancelAnimationFrame(frame);
  }, [handle, store, windowS, paused, zoom, serverNow, scalesKey]);

  return (
    <TimeChart
      series={store.labels().map((label, i) => ({ label, scale: scales[i], unit: units[i] }))}
      label={`Live chart of ${store.labels().join(", ")}`}
      onReady={setHandle}
      onZoom={onZoom}
      onResetZoom={onFollow}
    />
  );
}

/** The window ending now on the server's clock, or at the newest sample if a device clock is
 * ahead of it. */
function followRange(store: LiveStore, windowS: number, serverNow: () => number): [number, number] {
  const end = Math.max(serverNow(), store.latestTime() ?? -Infinity);
  return [end - windowS, end];
}
