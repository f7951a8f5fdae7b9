// Turning history answers into chart data, and the History tab's time ranges and buckets.
import type { AggregateAnswer, AggregateFn, DownsampleAnswer, TimedSample, TimeRange } from "../../api/history";
import type { AlignedSeries } from "../../live/decimate";
import { stepFrame, type ChartFrame, type TimedValue } from "./steps";

export const PRESETS: { value: string; label: string; seconds: number }[] = [
  { value: "15m", label: "last 15 min", seconds: 900 },
  { value: "1h", label: "last 1 h", seconds: 3600 },
  { value: "6h", label: "last 6 h", seconds: 6 * 3600 },
  { value: "24h", label: "last 24 h", seconds: 86400 },
  { value: "7d", label: "last 7 d", seconds: 7 * 86400 },
];

export const BUCKETS: { value: string; seconds: number }[] = [
  { value: "1s", seconds: 1 },
  { value: "10s", seconds: 10 },
  { value: "1m", seconds: 60 },
  { value: "10m", seconds: 600 },
  { value: "1h", seconds: 3600 },
  { value: "1d", seconds: 86400 },
];

/** A preset ("1h") or a custom range: `datetime-local` values, in this browser's zone. */
export type RangeChoice = { preset: string } | { from: string; to: string };

/** A datetime-local value ("2026-11-21T10:00") as ISO 8601 UTC; the API reads a time without
 * a zone as UTC, so the local time must be converted here. */
export function localToIso(value: string): string | undefined {
  if (!value) return undefined;
  const date = new Date(value);
  return Number.isNaN(date.getTime()) ? undefined : date.toISOString();
}

/** A time (seconds since the epoch) as a datetime-local value in this browser's zone. */
export function isoToLocal(seconds: number): string {
  const date = new Date(seconds * 1000);
  const pad = (n: number) => String(n).padStart(2, "0");
  return (
    `${date.getFullYear()}-${pad(date.getMonth() + 1)}-${pad(date.getDate())}` +
    `T${pad(date.getHours())}:${pad(date.getMinutes())}:${pad(date.getSeconds())}`
  );
}

export function toTimeRange(choice: RangeChoice): TimeRange {
  if ("preset" in choice) return { start: `-${choice.preset}` };
  return { start: localToIso(choice.from), end: localToIso(choice.to) };
}

/** The range's length in seconds (an open custom end is now). */
export function rangeSeconds(choice: RangeChoice, nowMs: number = Date.now()): number {
  if ("preset" in choice) return PRESETS.find((p) => p.value === choice.preset)?.seconds ?? 3600;
  const from = choice.from ? new Date(choice.from).getTime() : nowMs - 3600_000;
  const to = choice.to ? new Date(choice.to).getTime() : nowMs;
  return Math.max(1, (to - from) / 1000);
}

/** The smallest bucket that gives no more buckets than `columns` over the range. */
export function autoBucket(seconds: number, columns: number): string {
  const fit = BUCKETS.find((b) => seconds / b.seconds <= columns);
  return (fit ?? BUCKETS[BUCKETS.length - 1]!).value;
}

/** Series with their own times (ns) on one shared, sorted x (seconds); null where a series
 * has no value at a time. */
export function joinSeries(series: { time: number[]; value: number[] }[]): AlignedSeries {
  const all = new Float64Array(series.reduce((n, s) => n + s.time.length, 0));
  let k = 0;
  for (const s of series) for (const t of s.time) all[k++] = t;
  all.sort();
  const x: number[] = [];
  for (let i = 0; i < all.length; i++) if (i === 0 || all[i] !== all[i - 1]) x.push(all[i] as number);
  const index = new Map<number, number>();
  x.forEach((t, i) => index.set(t, i));
  const ys = series.map((s) => {
    const y: (number | null)[] = new Array<number | null>(x.length).fill(null);
    s.time.forEach((t, i) => (y[index.get(t) as number] = s.value[i] ?? null));
    return y;
  });
  return [x.map((t) => t / 1e9), ...ys];
}

/** An answer's view in seconds: from its start (or its first point, if earlier: aggregate
 * buckets are aligned to the epoch) to its end, or to when it was loaded for an open end
 * (or its last point, if a device's clock is ahead). */
function view(startNs: number | null | undefined, endNs: number | null | undefined, loadedAtMs: number, x: number[]): [number, number] {
  const first = x[0];
  const last = x[x.length - 1];
  let start = startNs === null || startNs === undefined ? (first ?? loadedAtMs / 1000) : startNs / 1e9;
  if (first !== undefined && first < start) start = first;
  let end = endNs === null || endNs === undefined ? loadedAtMs / 1000 : endNs / 1e9;
  if (last !== undefined && last > end) end = last;
  return [start, Math.max(end, start)];
}

/** The values before the range, in series order, in seconds. */
function beforeOf(signals: string[], before: Record<string, TimedSample>): (TimedValue | null)[] {
  return signals.map((name) => {
    const sample = before[name];
    return sample ? { time: sample.time / 1e9, value: sample.value } : null;
  });
}

export interface HistoryFrame {
  frame: ChartFrame;
  range: [number, number];
}

/** A downsample as steps held to the range's end, from the values before its start. */
export function downsampleFrame(answer: DownsampleAnswer, signals: string[], before: Record<string, TimedSample>, loadedAtMs: number): HistoryFrame {
  const data = joinSeries(signals.map((name) => answer.signals[name] ?? { time: [], value: [] }));
  const range = view(answer.start, answer.end, loadedAtMs, data[0]);
  return { frame: stepFrame(data, { start: range[0], end: range[1], before: beforeOf(signals, before) }), range };
}

/** A count or a sum of one bucket says nothing of the next: those are not held. */
export function holdsValue(fn: AggregateFn): boolean {
  return fn !== "count" && fn !== "sum";
}

/** Aggregate rows as steps: each bucket's value from its start to the next bucket's. */
export function aggregateFrame(
  answer: AggregateAnswer,
  signals: string[],
  fn: AggregateFn,
  before: Record<string, TimedSample>,
  loadedAtMs: number,
): HistoryFrame {
  const x = answer.rows.map((row) => row.time / 1e9);
  const ys = signals.map((name) => answer.rows.map((row) => row.values[name]?.[fn] ?? null));
  const range = view(answer.start, answer.end, loadedAtMs, x);
  const hold = holdsValue(fn);
  const options = { start: range[0], end: range[1], before: hold ? beforeOf(signals, before) : undefined, hold };
  return { frame: stepFrame([x, ...ys], options), range };
}

/** The signals whose first point comes later than one bucket after the range's start (or that
 * have none): their value before the start is worth asking for. */
export function signalsWithoutStart(firstTimes: Map<string, number | undefined>, startNs: number, bucketNs: number): string[] {
  return [...firstTimes].filter(([, first]) => first === undefined || first > startNs + bucketNs).map(([name]) => name);
}

/** Per signal, the time (ns) of its first point in a downsample. */
export function firstTimesOfDownsample(answer: DownsampleAnswer, signals: string[]): Map<string, number | undefined> {
  return new Map(signals.map((name) => [name, answer.signals[name]?.time[0]]));
}

/** Per signal, the time (ns) of the first bucket with its value. */
export function firstTimesOfAggregate(answer: AggregateAnswer, signals: string[], fn: AggregateFn): Map<string, number | undefined> {
  return new Map(
    signals.map((name) => [name, answer.rows.find((row) => typeof row.values[name]?.[fn] === "number")?.time]),
  );
}

export interface SignalSummary {
  signal: string;
  points: number;
  min: number | null;
  max: number | null;
  first: number | null;
  last: number | null;
}

/** Per signal of a min/max downsample: its extremes are the range's true extremes. */
export function summarize(answer: DownsampleAnswer, signals: string[]): SignalSummary[] {
  return signals.map((signal) => {
    const s = answer.signals[signal] ?? { time: [], value: [] };
    const n = s.value.length;
    return {
      signal,
      points: n,
      min: n ? s.value.reduce((a, b) => Math.min(a, b)) : null,
      max: n ? s.value.reduce((a, b) => Math.max(a, b)) : null,
      first: n ? (s.time[0] as number) / 1e9 : null,
      last: n ? (s.time[n - 1] as number) / 1e9 : null,
    };
  });
}
