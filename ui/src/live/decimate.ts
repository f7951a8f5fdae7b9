import type { RingBuffer } from "./ringBuffer";

/** Data for a chart with one shared x array: x, then one y array per series (null = no value
 * there), as uPlot takes it. */
export type AlignedSeries = [number[], ...(number | null)[][]];

/** Per pixel column of one series: how many samples fell in it, and its smallest and largest
 * sample (value and time). */
export interface Columns {
  count: Uint32Array;
  min: Float64Array;
  max: Float64Array;
  minTime: Float64Array;
  maxTime: Float64Array;
}

export function newColumns(n: number): Columns {
  return {
    count: new Uint32Array(n),
    min: new Float64Array(n),
    max: new Float64Array(n),
    minTime: new Float64Array(n),
    maxTime: new Float64Array(n),
  };
}

/** Fold one sample into column `c`. */
export function addToColumn(cols: Columns, c: number, t: number, v: number): void {
  if (cols.count[c] === 0) {
    cols.min[c] = cols.max[c] = v;
    cols.minTime[c] = cols.maxTime[c] = t;
  } else if (v < (cols.min[c] as number)) {
    cols.min[c] = v;
    cols.minTime[c] = t;
  } else if (v > (cols.max[c] as number)) {
    cols.max[c] = v;
    cols.maxTime[c] = t;
  }
  cols.count[c] = (cols.count[c] as number) + 1;
}

function scanColumns(buffer: RingBuffer, xMin: number, xMax: number, columns: number): Columns {
  const out = newColumns(columns);
  const scale = columns / (xMax - xMin);
  const length = buffer.length;
  for (let i = buffer.lowerBound(xMin); i < length; i++) {
    const t = buffer.timeAt(i);
    if (t > xMax) break;
    if (t < xMin) continue; // a late sample out of order
    const v = buffer.valueAt(i);
    if (!Number.isNaN(v)) addToColumn(out, Math.min(columns - 1, Math.floor((t - xMin) * scale)), t, v);
  }
  return out;
}

/** Two slots per column: the extreme that came first goes in the first slot, so the line
 * runs min→max or max→min as the data did. A column of one sample uses the first slot only. */
function fillSlots(cols: Columns, c: number, y: (number | null)[]): void {
  const n = cols.count[c] as number;
  if (n === 0) return;
  const min = cols.min[c] as number;
  const max = cols.max[c] as number;
  if (n === 1 || min === max) {
    y[2 * c] = min;
  } else if ((cols.minTime[c] as number) <= (cols.maxTime[c] as number)) {
    y[2 * c] = min;
    y[2 * c + 1] = max;
  } else {
    y[2 * c] = max;
    y[2 * c + 1] = min;
  }
}

/** The chart data of `n` columns per series, column c spanning [x0 + c·width, x0 + (c+1)·width):
 * one shared x grid (each column's quarter and three-quarter points). Slots where no series
 * has a value are left out, but for one per run of them: that null tells the chart where the
 * data stops (it decides whether the stretch is a gap worth breaking the line for). */
export function alignColumns(series: Columns[], x0: number, width: number, n: number): AlignedSeries {
  const slots = 2 * n;
  const ys = series.map((cols) => {
    const y: (number | null)[] = new Array<number | null>(slots).fill(null);
    for (let c = 0; c < n; c++) fillSlots(cols, c, y);
    return y;
  });
  const x: number[] = [];
  const kept: (number | null)[][] = ys.map(() => []);
  const emit = (s: number) => {
    x.push(x0 + (Math.floor(s / 2) + (s % 2 === 0 ? 0.25 : 0.75)) * width);
    ys.forEach((y, k) => (kept[k] as (number | null)[]).push(y[s] as number | null));
  };
  const has = (s: number) => ys.some((y) => y[s] !== null);
  let previousEmpty = true;
  for (let c = 0; c < n; c++) {
    const first = has(2 * c);
    const second = has(2 * c + 1);
    if (first) emit(2 * c);
    if (second) emit(2 * c + 1);
    const empty = !first && !second;
    if (empty && !previousEmpty) emit(2 * c); // one null for a run of empty columns
    previousEmpty = empty;
  }
  return [x, ...kept];
}

/** Decimate several series over [xMin, xMax] to at most two points per pixel column each, on
 * one shared x grid. Every column's smallest and largest value is kept, so a one-sample spike
 * still shows. The output never has more than 2 × `columns` points, however many samples the
 * buffers hold. This scans every sample in the range; LiveDecimator does the same work
 * incrementally for a window that follows live data. */
export function decimateMinMax(buffers: RingBuffer[], xMin: number, xMax: number, columns: number): AlignedSeries {
  columns = Math.max(1, Math.floor(columns));
  if (!(xMax > xMin)) return [[], ...buffers.map(() => [])];
  const scanned = buffers.map((buffer) => scanColumns(buffer, xMin, xMax, columns));
  return alignColumns(scanned, xMin, (xMax - xMin) / columns, columns);
}
