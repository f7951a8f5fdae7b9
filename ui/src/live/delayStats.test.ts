import { describe, expect, it } from "vitest";
import { ObservationWindow, StreamStats } from "./delayStats";

describe("ObservationWindow", () => {
  it("answers the median and the nearest-rank p99 of the recent values", () => {
    const window = new ObservationWindow(1000);
    for (let v = 1; v <= 100; v++) window.add(10_000, v);
    expect(window.percentiles(10_000, 5000)).toEqual({ median: 50, p99: 99, count: 100 });
  });

  it("forgets values older than the span", () => {
    const window = new ObservationWindow(100);
    window.add(1000, 500);
    window.add(9000, 10);
    expect(window.percentiles(10_000, 5000)).toEqual({ median: 10, p99: 10, count: 1 });
    expect(window.percentiles(20_000, 5000)).toBeNull();
    expect(window.sum(10_000, 5000)).toBe(10);
  });

  it("holds at most its capacity", () => {
    const window = new ObservationWindow(4);
    for (let v = 1; v <= 10; v++) window.add(0, v);
    expect(window.percentiles(0, 1000)?.count).toBe(4);
    expect(window.percentiles(0, 1000)?.median).toBe(8);
  });
});

describe("StreamStats", () => {
  const ms = 1e6;
  it("measures sent − sample time, sent − received and the rate", () => {
    const stats = new StreamStats(5000);
    const now = 100_000;
    // a batch of 3 samples taken 30, 20 and 10 ms before it was sent, 2 ms in the platform
    stats.addMessage(now, 1000 * ms, 1002 * ms, [972 * ms, 982 * ms, 992 * ms]);
    const snap = stats.snapshot(now);
    expect(snap.delay).toEqual({ median: 20, p99: 30, count: 3 });
    expect(snap.platform).toEqual({ median: 2, p99: 2, count: 1 });
    expect(snap.samplesPerSecond).toBe(3); // over the first second
    stats.addDropped(2, 500);
    expect(stats.snapshot(now)).toMatchObject({ droppedMessages: 2, droppedSamples: 500 });
  });

  it("records a bounded number of delays per large batch", () => {
    const stats = new StreamStats();
    const times = Array.from({ length: 500 }, (_, i) => i * ms);
    stats.addMessage(0, 600 * ms, 600 * ms, times);
    const snap = stats.snapshot(0);
    expect(snap.delay!.count).toBeLessThanOrEqual(16);
    expect(snap.delay!.median).toBeGreaterThan(100);
    expect(snap.samplesPerSecond).toBe(500);
  });
});
