import { describe, expect, it } from "vitest";
import { decimateMinMax } from "./decimate";
import { RingBuffer } from "./ringBuffer";

function filled(times: number[], value: (t: number, i: number) => number): RingBuffer {
  const buffer = new RingBuffer(Math.max(1, times.length));
  times.forEach((t, i) => buffer.push(t, value(t, i)));
  return buffer;
}

describe("decimateMinMax", () => {
  it("bounds the output by two points per column, however many samples there are", () => {
    const times = Array.from({ length: 100_000 }, (_, i) => i / 10_000); // 10 s at 10 kHz
    const buffer = filled(times, (t) => Math.sin(t * 20));
    const [x, y] = decimateMinMax([buffer], 0, 10, 500);
    expect(x.length).toBeLessThanOrEqual(1000);
    expect(y).toHaveLength(x.length);
    expect(x.length).toBeGreaterThan(900);
  });

  it("keeps a one-sample spike", () => {
    const times = Array.from({ length: 50_000 }, (_, i) => i / 1000);
    const buffer = filled(times, (_, i) => (i === 31_337 ? 99 : i === 4_242 ? -42 : 0));
    const [, y] = decimateMinMax([buffer], 0, 50, 100);
    const values = y as number[];
    expect(Math.max(...values.filter((v) => v !== null))).toBe(99);
    expect(Math.min(...values.filter((v) => v !== null))).toBe(-42);
  });

  it("keeps the order in which min and max came within a column", () => {
    const buffer = filled([0.1, 0.2, 0.3], (_, i) => [5, -5, 0][i] as number);
    const [x, y] = decimateMinMax([buffer], 0, 1, 1);
    expect(y).toEqual([5, -5]);
    expect(x[0]).toBeLessThan(x[1] as number);
  });

  it("aligns several series on one x and leaves gaps as null", () => {
    const a = filled([0.5, 1.5], () => 1);
    const b = filled([2.5], () => 2);
    const [x, ya, yb] = decimateMinMax([a, b], 0, 3, 3);
    expect(x).toEqual([0.25, 1.25, 2.25]);
    expect(ya).toEqual([1, 1, null]);
    expect(yb).toEqual([null, null, 2]);
  });

  it("leaves out samples outside the range and answers nothing for an empty range", () => {
    const buffer = filled([1, 2, 3, 4], () => 1);
    const [x, y] = decimateMinMax([buffer], 2, 3, 10);
    // the empty columns between the two samples leave one null, where the data stops
    expect(x.map((v) => Math.round(v * 1000) / 1000)).toEqual([2.025, 2.125, 2.925]);
    expect(y).toEqual([1, null, 1]);
    expect(decimateMinMax([buffer], 3, 3, 10)).toEqual([[], []]);
  });
});
