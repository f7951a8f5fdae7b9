// Which series share the left y axis and which go on a second one on the right: when the
// sizes of the values differ by orders of magnitude (a stress in Pa beside an angle in rad),
// one axis would flatten the small ones to a line.

export type ScaleKey = "y" | "y2";

/** Orders of magnitude between two groups before they get an axis each. */
const SPLIT_DECADES = 2;

/** The largest absolute value of a series (0 when it has none). */
export function magnitude(values: ArrayLike<number | null | undefined>): number {
  let largest = 0;
  for (let i = 0; i < values.length; i++) {
    const v = values[i];
    if (v !== null && v !== undefined && Math.abs(v) > largest) largest = Math.abs(v);
  }
  return largest;
}

/** Split the series at the widest gap between their magnitudes (in decades) when it is at
 * least SPLIT_DECADES wide; the first series' side keeps the left axis. Series without
 * values stay on the left. */
export function assignScales(magnitudes: number[]): ScaleKey[] {
  const logs = magnitudes.map((m) => (m > 0 ? Math.log10(m) : null));
  const known = [...new Set(logs.filter((l): l is number => l !== null))].sort((a, b) => a - b);
  let gap = 0;
  let cut = 0;
  for (let i = 1; i < known.length; i++) {
    const width = (known[i] as number) - (known[i - 1] as number);
    if (width > gap) {
      gap = width;
      cut = ((known[i] as number) + (known[i - 1] as number)) / 2;
    }
  }
  if (gap < SPLIT_DECADES) return magnitudes.map(() => "y");
  const firstLog = logs.find((l) => l !== null) as number;
  const firstHigh = firstLog > cut;
  return logs.map((l) => (l === null || l > cut === firstHigh ? "y" : "y2"));
}
