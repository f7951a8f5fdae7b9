import { describe, expect, it } from "vitest";
import { decimateMinMax } from "./decimate";
import { LiveDecimator } from "./liveDecimator";
import { RingBuffer } from "./ringBuffer";

function values(series: (number | null)[]): number[] {
  return series.filter((v): v is number => v !== null);
}

describe("LiveDecimator", () => {
  it("gives the columns a full scan of the same grid gives, frame after frame", () => {
    const a = new RingBuffer(100_000);
    const b = new RingBuffer(100_000);
    const live = new LiveDecimator([a, b]);
    let t = 1_700_000_000;
    for (let frame = 0; frame < 40; frame++) {
      for (let i = 0; i < 170; i++) {
        t += 1e-4;
        a.push(t, Math.sin(t * 7));
        if (i % 3 === 0) b.push(t, Math.cos(t * 3) * 1000);
      }
      const end = t + 0.004;
      const incremental = live.frame(end, 1, 100);
      const width = 1 / 100;
      const first = Math.floor((end - 1) / width);
      const n = Math.floor(end / width) - first + 1;
      const fresh = decimateMinMax([a, b], first * width, (first + n) * width, n);
      expect(incremental[0].length).toBeLessThanOrEqual(2 * n);
      expect(values(incremental[1]!)).toEqual(values(fresh[1]!));
      expect(values(incremental[2]!)).toEqual(values(fresh[2]!));
    }
  });

  it("starts over only when the column width changes, whatever the window's end", () => {
    const buffer = new RingBuffer(10);
    const live = new LiveDecimator([buffer]);
    for (let i = 0; i < 5000; i++) live.frame(1_763_795_000.123 + i * 0.0167 + Math.random() * 1e-3, 300, 813);
    expect(live.resets).toBe(1);
    live.frame(1_763_795_100, 30, 813);
    expect(live.resets).toBe(2);
  });

  it("keeps a spike and forgets columns that scrolled out of the window", () => {
    const buffer = new RingBuffer(10_000);
    const live = new LiveDecimator([buffer]);
    for (let i = 0; i < 5000; i++) buffer.push(i / 1000, i === 1234 ? 50 : 0);
    expect(Math.max(...values(live.frame(5, 5, 50)[1]!))).toBe(50);
    for (let i = 5000; i < 9000; i++) buffer.push(i / 1000, 0);
    const [x, y] = live.frame(9, 5, 50);
    expect(Math.max(...values(y!))).toBe(0);
    expect(Math.min(...x)).toBeGreaterThanOrEqual(3.9);
  });

  it("starts over when the buffer is cleared or history is put before it", () => {
    const buffer = new RingBuffer(1000);
    const live = new LiveDecimator([buffer]);
    buffer.push(9.5, 1);
    expect(values(live.frame(10, 10, 10)[1]!)).toEqual([1]);
    buffer.prependOlder([2.5, 3.5], [7, 8]);
    expect(values(live.frame(10, 10, 10)[1]!)).toEqual([7, 8, 1]);
    buffer.clear();
    expect(live.frame(10, 10, 10)[0]).toEqual([]);
  });

  it("ignores a late sample for a column that has scrolled away", () => {
    const buffer = new RingBuffer(1000);
    const live = new LiveDecimator([buffer]);
    for (let i = 0; i <= 100; i++) buffer.push(i, 1);
    live.frame(100, 10, 10);
    buffer.push(3, 99); // far older than the window, in the slot of a newer column
    expect(values(live.frame(100, 10, 10)[1]!)).not.toContain(99);
  });
});
