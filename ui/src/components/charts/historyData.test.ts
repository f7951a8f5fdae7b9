import { describe, expect, it } from "vitest";
import type { AggregateAnswer } from "../../api/history";
import {
  aggregateFrame,
  autoBucket,
  downsampleFrame,
  firstTimesOfAggregate,
  firstTimesOfDownsample,
  isoToLocal,
  joinSeries,
  localToIso,
  rangeSeconds,
  signalsWithoutStart,
  summarize,
  toTimeRange,
} from "./historyData";

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

  it("draws a signal with few samples in the range as steps held to the range's end", () => {
    // Last 15 minutes up to 1000 s; a signal sent on change: 0.5 since before the range, 2 from 400 s.
    const answer = { stream: "t", start: 100e9, end: null, points: 1000, skipped: [], signals: { crane_x: { time: [400e9], value: [2] } } };
    const { frame, range } = downsampleFrame(answer, ["crane_x"], { crane_x: { time: 50e9, value: 0.5 } }, 1_000_000);
    expect(range).toEqual([100, 1000]);
    expect(frame.data).toEqual([
      [100, 250, 400],
      [0.5, null, 2],
    ]);
    expect(frame.held).toEqual([
      { series: 0, from: 100, to: 400, value: 0.5 },
      { series: 0, from: 400, to: 1000, value: 2 },
    ]);
    // With nothing in the range at all, the value from before holds over all of it.
    const empty = downsampleFrame({ ...answer, end: 900e9, signals: {} }, ["crane_x"], { crane_x: { time: 50e9, value: 0.5 } }, 1_000_000);
    expect(empty.range).toEqual([100, 900]);
    expect(empty.frame.held).toEqual([{ series: 0, from: 100, to: 900, value: 0.5 }]);
  });

  it("turns aggregate rows into steps per signal, holding averages but not counts", () => {
    const answer: AggregateAnswer = {
      stream: "t", start: 60e9, end: 300e9, bucket: "1m", bucket_ns: 60e9, fn: ["max"], skipped: [],
      rows: [
        { time: 60e9, values: { a: { max: 2 }, b: { max: 5 } } },
        { time: 120e9, values: { a: { max: 3 } } },
      ],
    };
    const max = aggregateFrame(answer, ["a", "b"], "max", {}, 0);
    expect(max.range).toEqual([60, 300]);
    expect(max.frame.data).toEqual([
      [60, 120],
      [2, 3],
      [5, undefined],
    ]);
    expect(max.frame.held.map((h) => [h.series, h.from, h.to])).toEqual([
      [0, 120, 300],
      [1, 60, 300],
    ]);
    expect(aggregateFrame(answer, ["a", "b"], "count", {}, 0).frame.held).toEqual([]);
  });

  it("asks for the value before the range only of signals that start late in it", () => {
    const answer = { stream: "t", start: 0, end: 0, points: 4, skipped: [], signals: { early: { time: [1e9, 9e9], value: [1, 2] }, late: { time: [5e9], value: [3] } } };
    expect(signalsWithoutStart(firstTimesOfDownsample(answer, ["early", "late", "none"]), 0, 2e9)).toEqual(["late", "none"]);
    const rows = { stream: "t", bucket: "1s", bucket_ns: 1e9, fn: ["avg" as const], skipped: [], rows: [{ time: 3e9, values: { a: { avg: 1 }, b: { avg: null } } }] };
    expect(firstTimesOfAggregate(rows, ["a", "b"], "avg")).toEqual(new Map([["a", 3e9], ["b", undefined]]));
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
