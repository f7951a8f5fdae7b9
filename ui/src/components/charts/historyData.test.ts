import { describe, expect, it } from "vitest";
import type { AggregateAnswer } from "../../api/history";
import { aggregateSeries, autoBucket, markGaps, isoToLocal, joinSeries, localToIso, rangeSeconds, summarize, toTimeRange } from "./historyData";

describe("history data", () => {
  it("joins series of their own times on one x in seconds", () => {
    const data = joinSeries([
      { time: [1e9, 3e9], value: [1, 3] },
      { time: [2e9, 3e9], value: [20, 30] },
    ]);
    expect(data).toEqual([
      [1, 2, 3],
      [1, null, 3],
      [null, 20, 30],
    ]);
  });

  it("marks a stretch without data so the line breaks there", () => {
    const data = markGaps([
      [0, 1, 2, 3, 4, 5, 100, 101],
      [1, 2, 3, 4, 5, 6, 7, 8],
    ]);
    expect(data).toEqual([
      [0, 1, 2, 3, 4, 5, 52.5, 100, 101],
      [1, 2, 3, 4, 5, 6, null, 7, 8],
    ]);
    expect(markGaps([[0, 1, 2], [1, 1, 1]])).toEqual([[0, 1, 2], [1, 1, 1]]);
    // min/max pairs: a short step inside each bucket, a longer one between buckets
    const pairs = [0, 0.01, 2, 2.01, 4, 4.01, 6, 6.01];
    expect(markGaps([pairs, pairs.map(() => 1)])[0]).toEqual(pairs);
  });

  it("turns aggregate rows into one series per signal", () => {
    const answer: AggregateAnswer = {
      stream: "t", bucket: "1m", bucket_ns: 60e9, fn: ["max"], skipped: [],
      rows: [
        { time: 60e9, values: { a: { max: 2 }, b: { max: 5 } } },
        { time: 120e9, values: { a: { max: 3 } } },
      ],
    };
    expect(aggregateSeries(answer, ["a", "b"], "max")).toEqual([
      [60, 120],
      [2, 3],
      [5, null],
    ]);
  });

  it("chooses the smallest bucket that fits the columns", () => {
    expect(autoBucket(900, 1000)).toBe("1s");
    expect(autoBucket(3600, 1000)).toBe("10s");
    expect(autoBucket(7 * 86400, 1000)).toBe("1h"); // 1 008 buckets of 10m would be too many
    expect(autoBucket(6 * 86400, 1000)).toBe("10m");
    expect(autoBucket(1e9, 1000)).toBe("1d");
  });

  it("turns presets and local custom ranges into API ranges", () => {
    expect(toTimeRange({ preset: "6h" })).toEqual({ start: "-6h" });
    expect(rangeSeconds({ preset: "7d" })).toBe(7 * 86400);
    const local = isoToLocal(Date.UTC(2026, 10, 21, 10, 0, 0) / 1000);
    expect(localToIso(local)).toBe("2026-11-21T10:00:00.000Z");
    expect(toTimeRange({ from: local, to: "" })).toEqual({ start: "2026-11-21T10:00:00.000Z", end: undefined });
    expect(rangeSeconds({ from: local, to: isoToLocal(Date.UTC(2026, 10, 21, 11, 0, 0) / 1000) })).toBe(3600);
  });

  it("summarizes a downsample per signal", () => {
    const answer = { stream: "t", start: 0, end: 0, points: 4, skipped: [], signals: { a: { time: [1e9, 2e9, 3e9], value: [4, -1, 7] } } };
    expect(summarize(answer, ["a", "b"])).toEqual([
      { signal: "a", points: 3, min: -1, max: 7, first: 1, last: 3 },
      { signal: "b", points: 0, min: null, max: null, first: null, last: null },
    ]);
  });
});
