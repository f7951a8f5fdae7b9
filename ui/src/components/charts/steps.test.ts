import { describe, expect, it } from "vitest";
import { stepFrame, usualSpan } from "./steps";

const u = undefined;

describe("steps", () => {
  it("measures the usual span of two steps, not fooled by min/max pairs", () => {
    expect(usualSpan([0, 0.01, 2, 2.01, 4, 4.01, 6])).toBe(2);
    expect(usualSpan([0, 1])).toBeNull();
  });

  it("holds a signal's only sample, from long ago, to now: dashed", () => {
    // One sample 50 s before the end of a 30 s window that has none: known from before.
    const frame = stepFrame([[], []], { start: 70, end: 100, before: [{ time: 50, value: 2.5 }] });
    expect(frame.data).toEqual([[70], [2.5]]);
    expect(frame.held).toEqual([{ series: 0, from: 70, to: 100, value: 2.5 }]);
  });

  it("holds the last sample to the end of the view", () => {
    // A steady signal whose newest sample is one step old: the solid line reaches the end.
    const steady = stepFrame([[1, 2, 3, 4], [1, 2, 3, 4]], { start: 0, end: 5 });
    expect(steady.data).toEqual([[1, 2, 3, 4, 5], [1, 2, 3, 4, 4]]);
    expect(steady.held).toEqual([]);
    // Sent on change: it stopped changing long ago, so the rest is held, dashed, to the end.
    const still = stepFrame([[1, 2, 3, 4], [1, 2, 3, 4]], { start: 0, end: 60 });
    expect(still.data).toEqual([[1, 2, 3, 4], [1, 2, 3, 4]]);
    expect(still.held).toEqual([{ series: 0, from: 4, to: 60, value: 4 }]);
  });

  it("breaks the solid line where a value was held for long, and draws the hold", () => {
    const frame = stepFrame([[0, 1, 2, 3, 4, 50, 51], [5, 6, 7, 8, 9, 10, 11]], { start: 0, end: 51 });
    expect(frame.data).toEqual([
      [0, 1, 2, 3, 4, 27, 50, 51],
      [5, 6, 7, 8, 9, null, 10, 11],
    ]);
    expect(frame.held).toEqual([{ series: 0, from: 4, to: 50, value: 9 }]);
  });

  it("draws the value from before the view from the view's start", () => {
    // Shortly before the first sample, as steady as the rest: solid.
    const near = stepFrame([[10, 11, 12, 13], [1, 2, 3, 4]], { start: 9.5, end: 13, before: [{ time: 9, value: 0 }] });
    expect(near.data).toEqual([[9.5, 10, 11, 12, 13], [0, 1, 2, 3, 4]]);
    expect(near.held).toEqual([]);
    // Long before: held up to the first sample, then measured.
    const far = stepFrame([[100, 101, 102], [1, 2, 3]], { start: 90, end: 102, before: [{ time: 0, value: 7 }] });
    expect(far.data).toEqual([[90, 95, 100, 101, 102], [7, null, 1, 2, 3]]);
    expect(far.held).toEqual([{ series: 0, from: 90, to: 100, value: 7 }]);
    // A sample at the view's start needs nothing from before.
    expect(stepFrame([[90], [1]], { start: 90, end: 90, before: [{ time: 0, value: 7 }] }).data).toEqual([[90], [1]]);
  });

  it("keeps the series apart on one x, undefined where one has no point", () => {
    const frame = stepFrame(
      [
        [1, 2, 3],
        [1, null, 3],
        [null, 20, null],
      ],
      { start: 0, end: 3, before: [null, { time: 0.5, value: 10 }] },
    );
    expect(frame.data[0]).toEqual([0, 1, 2, 3]);
    expect(frame.data[1]).toEqual([u, 1, u, 3]);
    expect(frame.data[2]).toEqual([10, null, 20, u]);
    // series 0 ends at the view's end; series 1 has too few samples to tell a usual step, so
    // its holds count as long
    expect(frame.held).toEqual([
      { series: 1, from: 0, to: 2, value: 10 },
      { series: 1, from: 2, to: 3, value: 20 },
    ]);
  });

  it("holds nothing for counts and sums, breaking the line where buckets are missing", () => {
    const frame = stepFrame([[0, 1, 2, 3, 4, 40], [5, 5, 5, 5, 5, 5]], { start: 0, end: 100, before: [{ time: -1, value: 1 }], hold: false });
    expect(frame.data).toEqual([
      [0, 1, 2, 3, 4, 22, 40],
      [5, 5, 5, 5, 5, null, 5],
    ]);
    expect(frame.held).toEqual([]);
  });

  it("has nothing to draw without samples or a value from before", () => {
    const frame = stepFrame([[], []], { start: 0, end: 10, before: [null] });
    expect(frame).toEqual({ data: [[], []], held: [] });
  });
});
