import { describe, expect, it } from "vitest";
import { capacityPerSignal, LiveStore, maxRateFor } from "./liveStore";

const REFS = [
  { stream: "telemetry", signal: "angle" },
  { stream: "telemetry", signal: "on" },
  { stream: "fmu", signal: "theta" },
];

function message(stream: string, samples: { time: number; values: Record<string, unknown> }[]) {
  return { type: "samples" as const, sub: "s1", twin: "tingen", stream, received: 0, sent: 0, samples };
}

describe("LiveStore", () => {
  it("counts every sample received and keeps the chosen numeric values", () => {
    const store = new LiveStore(REFS, 100);
    store.addSamples(
      message("telemetry", [
        { time: 1e9, values: { angle: 0.5, on: true, other: 3 } },
        { time: 2e9, values: { angle: "bad", on: false } },
      ]),
    );
    store.addSamples(message("fmu", [{ time: 3e9, values: { theta: 0.4 } }]));
    store.addSamples(message("elsewhere", [{ time: 4e9, values: { theta: 9 } }]));
    expect(store.points).toBe(3);
    expect(store.latestTime()).toBe(3);
    const [x, angle, on, theta] = store.frame(0, 4, 4);
    expect(x).toHaveLength(3);
    expect(angle).toEqual([0.5, null, null]);
    expect(on).toEqual([1, 0, null]);
    expect(theta).toEqual([null, null, 0.4]);
    expect(store.labels()).toEqual(["telemetry/angle", "telemetry/on", "fmu/theta"]);
  });

  it("puts history before the live data, and forgets data but not the count", () => {
    const store = new LiveStore(REFS, 100);
    store.addSamples(message("fmu", [{ time: 5e9, values: { theta: 1 } }]));
    store.backfill("fmu", {
      stream: "fmu", start: 0, end: 0, points: 10, skipped: [],
      signals: { theta: { time: [3e9, 4e9, 5e9], value: [7, 8, 9] } },
    });
    expect(store.frame(0, 6, 6)[3]!.filter((v) => v !== null)).toEqual([7, 8, 1]);
    store.clearData();
    expect(store.latestTime()).toBeUndefined();
    expect(store.points).toBe(1);
  });

  it("knows each signal's last value before a time: held, else the seed from the API", () => {
    const store = new LiveStore(REFS, 4);
    // Sent on change: the angle's only sample is from long before the window.
    store.seed("telemetry", { angle: { time: 10e9, value: 0.25 }, on: { time: 95e9, value: 1 } });
    expect(store.before(90)).toEqual([{ time: 10, value: 0.25 }, null, null]);
    store.addSamples(message("telemetry", [{ time: 92e9, values: { angle: 0.5 } }]));
    expect(store.before(90)[0]).toEqual({ time: 10, value: 0.25 });
    expect(store.before(93)[0]).toEqual({ time: 92, value: 0.5 });
    // Once the buffer has dropped samples, a seed may be older than a dropped one: unknown.
    for (let t = 100; t < 104; t++) store.addSamples(message("telemetry", [{ time: t * 1e9, values: { angle: t } }]));
    expect(store.before(90)[0]).toBeNull();
    store.clearData();
    expect(store.before(1000)).toEqual([null, null, null]);
  });

  it("limits the rate only when a window would not fit in memory", () => {
    expect(capacityPerSignal(2)).toBe(1 << 20);
    expect(maxRateFor(2, 10)).toBeUndefined();
    expect(maxRateFor(2, 900)).toBe(Math.floor((1 << 20) / 900));
    expect(maxRateFor(100, 60)).toBe(Math.floor((1 << 16) / 60));
  });
});
