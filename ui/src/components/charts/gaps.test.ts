import { describe, expect, it } from "vitest";
import { meanStep, realGaps } from "./gaps";

describe("gaps", () => {
  it("measures the usual step of a series among the nulls of others", () => {
    expect(meanStep([0, 1, 2, 3, 4, 10], [1, null, 2, null, 3, 4], 0, 5)).toBe(10 / 3);
    expect(meanStep([0, 1], [1, null], 0, 1)).toBeNull();
  });

  it("keeps only gaps much longer than the usual step", () => {
    const gaps: [number, number][] = [
      [0, 4],
      [10, 200],
    ];
    expect(realGaps(gaps, 1, 2)).toEqual([[10, 200]]); // 5 steps = 10 px
    expect(realGaps(gaps, null, 2)).toEqual([]);
  });
});
