import { describe, expect, it } from "vitest";
import { formatClock, formatInstant, formatTime, timeAxisValues } from "./time";

// Local times, so the expectations hold in any time zone.
const at = (h: number, m = 0, s = 0, ms = 0, day = 21) => new Date(2026, 10, day, h, m, s, ms);
const seconds = (d: Date) => d.getTime() / 1000;
const NBSP = "\u00a0";

describe("times in the user's locale", () => {
  it("formats dates in the given locale, never wrapping", () => {
    expect(formatTime(at(14, 5, 9).toISOString(), "en-US")).toBe(`11/21/26,${NBSP}2:05:09\u202fPM`.replace(/\s/g, NBSP));
    expect(formatTime(at(14, 5, 9).toISOString(), "de-DE")).toBe(`21.11.26,${NBSP}14:05:09`);
    expect(formatTime(null)).toBe("never");
    expect(formatTime("not a time")).toBe("not a time");
    expect(formatClock(at(14, 5, 9).getTime(), "en-GB")).toBe("14:05:09");
    expect(formatInstant(seconds(at(14, 5, 9, 250)), "en-GB")).toBe(`21${NBSP}Nov${NBSP}2026,${NBSP}14:05:09.250`);
  });

  it("labels time ticks as finely as their spacing, with the day where it changes", () => {
    const ticks = [at(23, 0), at(23, 30), at(0, 0, 0, 0, 22)].map(seconds);
    expect(timeAxisValues(ticks, 1800, "en-GB")).toEqual([`23:00\n21${NBSP}Nov`, "23:30", `00:00\n22${NBSP}Nov`]);
    expect(timeAxisValues([seconds(at(10, 0, 1, 500))], 0.5, "de-DE")).toEqual([`10:00:01,500\n21.${NBSP}Nov.`]);
    expect(timeAxisValues([seconds(at(10, 0, 1))], 10, "en-GB")[0]).toMatch(/^10:00:01\n/);
    expect(timeAxisValues([seconds(at(0))], 86400, "en-GB")).toEqual([`21${NBSP}Nov`]);
    expect(timeAxisValues([seconds(at(0))], 90 * 86400, "en-GB")).toEqual([`Nov${NBSP}2026`]);
  });
});
