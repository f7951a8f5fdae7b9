import { describe, expect, it } from "vitest";
import { RingBuffer } from "./ringBuffer";

function contents(buffer: RingBuffer): [number, number][] {
  return Array.from({ length: buffer.length }, (_, i) => [buffer.timeAt(i), buffer.valueAt(i)]);
}

describe("RingBuffer", () => {
  it("keeps the newest pairs once full, oldest first", () => {
    const buffer = new RingBuffer(3);
    for (let i = 1; i <= 5; i++) buffer.push(i, i * 10);
    expect(buffer.length).toBe(3);
    expect(contents(buffer)).toEqual([
      [3, 30],
      [4, 40],
      [5, 50],
    ]);
    expect(buffer.firstTime()).toBe(3);
    expect(buffer.lastTime()).toBe(5);
  });

  it("finds the first pair at or after a time across the wrap", () => {
    const buffer = new RingBuffer(4);
    for (let i = 1; i <= 6; i++) buffer.push(i, 0); // holds 3, 4, 5, 6
    expect(buffer.lowerBound(0)).toBe(0);
    expect(buffer.lowerBound(4)).toBe(1);
    expect(buffer.lowerBound(4.5)).toBe(2);
    expect(buffer.lowerBound(7)).toBe(4);
  });

  it("puts older history before the live pairs, skipping what overlaps", () => {
    const buffer = new RingBuffer(5);
    buffer.push(10, 1);
    buffer.push(11, 2);
    buffer.prependOlder([7, 8, 9, 10, 11], [7, 8, 9, 10, 11]);
    expect(contents(buffer)).toEqual([
      [7, 7],
      [8, 8],
      [9, 9],
      [10, 1],
      [11, 2],
    ]);
  });

  it("drops the oldest history when it does not all fit", () => {
    const buffer = new RingBuffer(3);
    buffer.push(10, 1);
    buffer.prependOlder([1, 2, 3, 4], [1, 2, 3, 4]);
    expect(contents(buffer).map(([t]) => t)).toEqual([3, 4, 10]);
  });

  it("refuses a capacity that is not a positive integer", () => {
    expect(() => new RingBuffer(0)).toThrow(RangeError);
  });
});
