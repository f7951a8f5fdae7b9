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

/** The usual span of two steps of `xs` (the median): min/max data comes in pairs close in
 * time, one pair per bucket, so a single step would mistake the pairs' gaps for long ones.
 * Null with fewer than three samples. */
export function usualSpan(xs: ArrayLike<number>): number | null {
  if (xs.length < 3) return null;
  const spans = new Float64Array(xs.length - 2);
  for (let i = 2; i < xs.length; i++) spans[i - 2] = (xs[i] as number) - (xs[i - 2] as number);
  spans.sort();
  return spans[spans.length >> 1] as number;
}

interface Plan {
  x: number[];
  y: (number | null)[];
}

/** One series' points: its samples, a value from before the view at its start, a null where
 * the solid line must stop for a held stretch, and its last value at the end when that hold is
 * short. Held stretches are added to `held`. */
function planSeries(xs: number[], ys: (number | null | undefined)[], k: number, options: StepOptions, held: Held[]): Plan {
  const hold = options.hold ?? true;
  const tx: number[] = [];
  const tv: number[] = [];
  for (let i = 0; i < xs.length; i++) {
    const v = ys[i];
    if (v !== null && v !== undefined && !Number.isNaN(v)) {
      tx.push(xs[i] as number);
      tv.push(v);
    }
  }
  const span = usualSpan(tx);
  const limit = span === null ? null : HELD_SPANS * span;
  // Without a usual step (too few samples) a hold to or from outside the samples counts as long.
  const isLong = (length: number) => (limit === null ? true : length > limit);
  const plan: Plan = { x: [], y: [] };
  const put = (x: number, y: number | null) => {
    plan.x.push(x);
    plan.y.push(y);
  };

  const first = tx[0];
  const before = hold ? options.before?.[k] : undefined;
  if (before && (first === undefined || first > options.start)) {
    const to = first ?? options.end;
    put(options.start, before.value);
    if (isLong(to - before.time)) {
      held.push({ series: k, from: options.start, to, value: before.value });
      if (first !== undefined) put((options.start + first) / 2, null);
    }
  }
  for (let i = 0; i < tx.length; i++) {
    const x = tx[i] as number;
    if (i > 0 && limit !== null && x - (tx[i - 1] as number) > limit) {
      const from = tx[i - 1] as number;
      if (hold) held.push({ series: k, from, to: x, value: tv[i - 1] as number });
      put((from + x) / 2, null);
    }
    put(x, tv[i] as number);
  }
  const last = tx.length - 1;
  if (hold && last >= 0 && options.end > (tx[last] as number)) {
    const from = tx[last] as number;
    const value = tv[last] as number;
    if (isLong(options.end - from)) held.push({ series: k, from, to: options.end, value });
    else put(options.end, value);
  }
  return plan;
}

/** The plans of all series on one shared x (sorted, each x once); undefined where a series
 * has no point. */
function merge(plans: Plan[]): ChartData {
  let n = 0;
  for (const p of plans) n += p.x.length;
  const all = new Float64Array(n);
  let k = 0;
  for (const p of plans) for (const x of p.x) all[k++] = x;
  all.sort();
  const x: number[] = [];
  for (let i = 0; i < all.length; i++) if (i === 0 || all[i] !== all[i - 1]) x.push(all[i] as number);
  const ys = plans.map((p) => {
    const y = new Array<number | null | undefined>(x.length).fill(undefined);
    let j = 0;
    for (let i = 0; i < p.x.length; i++) {
      while ((x[j] as number) < (p.x[i] as number)) j++;
      y[j] = p.y[i];
    }
    return y;
  });
  return [x, ...ys];
}

/** The chart frame of `data` (x sorted; null or undefined where a series has no value): each
 * series as steps held to `end`, from its value before `start` when known. Costs
 * O(points · log points); `data` is already thinned to the chart's columns. */
export function stepFrame(data: AlignedSeries | ChartData, options: StepOptions): ChartFrame {
  const [xs, ...ys] = data;
  const held: Held[] = [];
  const plans = ys.map((y, k) => planSeries(xs, y, k, options, held));
  return { data: merge(plans), held };
}

/** Whether a frame has anything to draw. */
export function frameIsEmpty(frame: ChartFrame): boolean {
  return frame.data[0].length === 0 && frame.held.length === 0;
}
