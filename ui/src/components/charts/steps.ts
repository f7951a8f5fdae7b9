// Every signal is drawn as steps: a sample's value holds until the next sample, and the last
// one holds to the end of the view ("now" when following live). Signals sent on change (an
// OPC UA subscription, a device that reports only what moved) have no samples while they keep
// their value; drawn point to point they vanished or broke off. A hold much longer than the
// signal's usual step between samples (it changes rarely, or its device went quiet) is drawn
// dashed instead of solid: the value is known, but no sample came over that stretch.
import type { AlignedSeries } from "../../live/decimate";

/** uPlot's data: x, then one array per series. A null breaks the series' line there; an
 * undefined (the series has no value at this x, another one has) does not. */
export type ChartData = [number[], ...(number | null | undefined)[][]];

/** A stretch over which series `series` (0-based, without x) holds `value` with no sample. */
export interface Held {
  series: number;
  from: number;
  to: number;
  value: number;
}

/** What a chart draws: the solid steps, and the held stretches drawn dashed over them. */
export interface ChartFrame {
  data: ChartData;
  held: Held[];
}

/** A sample (time in the chart's x unit, seconds). */
export interface TimedValue {
  time: number;
  value: number;
}

export interface StepOptions {
  /** The view's start: a value from before it (`before`) is drawn from here. */
  start: number;
  /** The view's end: each series' last value holds to here. */
  end: number;
  /** Per series, its last sample before `start`, if known. */
  before?: (TimedValue | null | undefined)[];
  /** False: nothing is held (a bucket's count or sum says nothing of the next bucket). A
   * long stretch without values then breaks the line. */
  hold?: boolean;
}

/** A stretch longer than this many usual spans between samples is held, not measured. */
const HELD_SPANS = 5;

/** The k-th smallest of `values` (reordering them): quickselect, O(n) on average. */
function select(values: Float64Array, k: number): number {
  let lo = 0;
  let hi = values.length - 1;
  while (lo < hi) {
    const pivot = values[(lo + hi) >> 1] as number;
    let i = lo;
    let j = hi;
    while (i <= j) {
      while ((values[i] as number) < pivot) i++;
      while ((values[j] as number) > pivot) j--;
      if (i <= j) {
        const t = values[i] as number;
        values[i++] = values[j] as number;
        values[j--] = t;
      }
    }
    if (k <= j) hi = j;
    else if (k >= i) lo = i;
    else break;
  }
  return values[k] as number;
}

/** The usual span of two steps of `xs` (the median): min/max data comes in pairs close in
 * time, one pair per bucket, so a single step would mistake the pairs' gaps for long ones.
 * Null with fewer than three samples. */
export function usualSpan(xs: ArrayLike<number>): number | null {
  if (xs.length < 3) return null;
  const spans = new Float64Array(xs.length - 2);
  for (let i = 2; i < xs.length; i++) spans[i - 2] = (xs[i] as number) - (xs[i - 2] as number);
  return select(spans, spans.length >> 1);
}

/** A point a series needs beside its samples: its value from before the view, a null where
 * its solid line stops for a held stretch, its last value at the view's end. */
interface Extra {
  series: number;
  x: number;
  y: number | null;
}

/** One series: the indices of its samples in `xs`, its extra points (added to `extras`) and
 * its held stretches (added to `held`). */
function planSeries(
  xs: number[],
  ys: (number | null | undefined)[],
  k: number,
  options: StepOptions,
  held: Held[],
  extras: Extra[],
): number[] {
  const hold = options.hold ?? true;
  const samples: number[] = [];
  const times: number[] = [];
  for (let i = 0; i < xs.length; i++) {
    const v = ys[i];
    if (v !== null && v !== undefined && !Number.isNaN(v)) {
      samples.push(i);
      times.push(xs[i] as number);
    }
  }
  const span = usualSpan(times);
  const limit = span === null ? null : HELD_SPANS * span;
  // Without a usual step (too few samples) a hold to or from outside the samples counts as long.
  const isLong = (length: number) => (limit === null ? true : length > limit);
  const valueAt = (n: number) => ys[samples[n] as number] as number;

  const first = times[0];
  const before = hold ? options.before?.[k] : undefined;
  if (before && (first === undefined || first > options.start)) {
    const to = first ?? options.end;
    extras.push({ series: k, x: options.start, y: before.value });
    if (isLong(to - before.time)) {
      held.push({ series: k, from: options.start, to, value: before.value });
      if (first !== undefined) extras.push({ series: k, x: (options.start + first) / 2, y: null });
    }
  }
  if (limit !== null) {
    for (let n = 1; n < times.length; n++) {
      const from = times[n - 1] as number;
      const x = times[n] as number;
      if (x - from <= limit) continue;
      if (hold) held.push({ series: k, from, to: x, value: valueAt(n - 1) });
      extras.push({ series: k, x: (from + x) / 2, y: null });
    }
  }
  const last = times.length - 1;
  if (hold && last >= 0 && options.end > (times[last] as number)) {
    const from = times[last] as number;
    const value = valueAt(last);
    if (isLong(options.end - from)) held.push({ series: k, from, to: options.end, value });
    else extras.push({ series: k, x: options.end, y: value });
  }
  return samples;
}

/** The first index of sorted `xs` whose value is at least `x`. */
function lowerBound(xs: number[], x: number): number {
  let lo = 0;
  let hi = xs.length;
  while (lo < hi) {
    const mid = (lo + hi) >>> 1;
    if ((xs[mid] as number) < x) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/** The frame of `data` (x sorted; null or undefined where a series has no value): each series
 * as steps held to `end`, from its value before `start` when known. O(points) but for the
 * median step; `data` is already thinned to the chart's columns. */
export function stepFrame(data: AlignedSeries | ChartData, options: StepOptions): ChartFrame {
  const [xs, ...ys] = data;
  const held: Held[] = [];
  const extras: Extra[] = [];
  const samples = ys.map((y, k) => planSeries(xs, y, k, options, held, extras));
  // One shared x: the xs some series has a sample at, and the extra points, in order.
  const used = new Uint8Array(xs.length);
  for (const list of samples) for (const i of list) used[i] = 1;
  const added = extras.map((e) => e.x).sort((a, b) => a - b);
  const x: number[] = [];
  const position = new Int32Array(xs.length);
  let e = 0;
  const take = (value: number) => {
    if (x.length === 0 || (x[x.length - 1] as number) !== value) x.push(value);
  };
  for (let i = 0; i < xs.length; i++) {
    if (!used[i]) continue;
    const value = xs[i] as number;
    while (e < added.length && (added[e] as number) < value) take(added[e++] as number);
    take(value);
    position[i] = x.length - 1;
  }
  while (e < added.length) take(added[e++] as number);
  const out = ys.map((y, k) => {
    const line = new Array<number | null | undefined>(x.length).fill(undefined);
    for (const i of samples[k] as number[]) line[position[i] as number] = y[i];
    return line;
  });
  for (const extra of extras) (out[extra.series] as (number | null | undefined)[])[lowerBound(x, extra.x)] = extra.y;
  return { data: [x, ...out], held };
}

/** Whether a frame has anything to draw. */
export function frameIsEmpty(frame: ChartFrame): boolean {
  return frame.data[0].length === 0 && frame.held.length === 0;
}
