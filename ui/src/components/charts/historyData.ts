// Turning history answers into chart data, and the History tab's time ranges and buckets.
import type { AggregateAnswer, AggregateFn, DownsampleAnswer, TimeRange } from "../../api/history";
import type { AlignedSeries } from "../../live/decimate";

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

/** Put an all-null point in the middle of each step of x much longer than usual (where the
 * data stops, as when a device was offline), so the chart can break its lines there instead
 * of drawing a straight line across. "Usual" is the median span of two steps: min/max data
 * comes in pairs close in time, one pair per bucket. */
export function markGaps(data: AlignedSeries, factor = 5): AlignedSeries {
  const [x, ...ys] = data;
  if (x.length < 3) return data;
  const spans = new Float64Array(x.length - 2);
  for (let i = 2; i < x.length; i++) spans[i - 2] = (x[i] as number) - (x[i - 2] as number);
  const limit = factor * (spans.sort()[spans.length >> 1] as number);
  const outX: number[] = [x[0] as number];
  const outYs: (number | null)[][] = ys.map((y) => [y[0] ?? null]);
  for (let i = 1; i < x.length; i++) {
    const step = (x[i] as number) - (x[i - 1] as number);
    if (step > limit) {
      outX.push((x[i - 1] as number) + step / 2);
      outYs.forEach((y) => y.push(null));
    }
    outX.push(x[i] as number);
    outYs.forEach((y, k) => y.push((ys[k] as (number | null)[])[i] ?? null));
  }
  return [outX, ...outYs];
}

export function downsampleSeries(answer: DownsampleAnswer, signals: string[]): AlignedSeries {
  return markGaps(joinSeries(signals.map((name) => answer.signals[name] ?? { time: [], value: [] })));
}

export function aggregateSeries(answer: AggregateAnswer, signals: string[], fn: AggregateFn): AlignedSeries {
  const x = answer.rows.map((row) => row.time / 1e9);
  const ys = signals.map((name) => answer.rows.map((row) => row.values[name]?.[fn] ?? null));
  return markGaps([x, ...ys]);
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
