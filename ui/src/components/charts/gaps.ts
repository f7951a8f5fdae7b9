// Where a line should break. Decimated series sit on one shared x grid, so a series has nulls
// wherever another series has a value or a pixel column holds no sample: those must not
// break its line. Only a stretch without values much longer than the series' usual step is
// a real gap (a device that was offline) and is drawn as one.

/** How many usual steps an empty stretch must last to be a gap. */
const GAP_STEPS = 5;

/** The mean step between the non-null values of `ys` in [idx0, idx1], in x units. */
export function meanStep(xs: ArrayLike<number>, ys: ArrayLike<number | null | undefined>, idx0: number, idx1: number): number | null {
  let first: number | null = null;
  let last = 0;
  let count = 0;
  for (let i = idx0; i <= idx1; i++) {
    if (ys[i] === null || ys[i] === undefined) continue;
    first ??= xs[i] as number;
    last = xs[i] as number;
    count++;
  }
  return first === null || count < 2 ? null : (last - first) / (count - 1);
}

/** Of the gaps uPlot found from nulls ([from, to] in canvas pixels), the ones wider than
 * GAP_STEPS usual steps; `pxPerUnit` converts x units to canvas pixels. */
export function realGaps(gaps: [number, number][], step: number | null, pxPerUnit: number): [number, number][] {
  if (step === null) return [];
  const minPx = GAP_STEPS * step * pxPerUnit;
  return gaps.filter(([from, to]) => to - from > minPx);
}
