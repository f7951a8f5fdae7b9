import { afterEach, describe, expect, it, vi } from "vitest";
import { jsonResponse, mockFetch } from "../test/fetch";
import { aggregateQuery, downsampleQuery, fileNameFrom, isPlottable, lastBefore } from "./history";

afterEach(() => vi.unstubAllGlobals());

describe("history API helpers", () => {
  it("reads the file name of a Content-Disposition header", () => {
    expect(fileNameFrom('attachment; filename="tingen-telemetry.csv"')).toBe("tingen-telemetry.csv");
    expect(fileNameFrom("attachment; filename=tingen-fmu.jsonl")).toBe("tingen-fmu.jsonl");
    expect(fileNameFrom("attachment; filename*=UTF-8''t%C3%A4st.csv")).toBe("täst.csv");
    expect(fileNameFrom("attachment")).toBeNull();
    expect(fileNameFrom(null)).toBeNull();
  });

  it("builds the query of a downsample and an aggregate", () => {
    expect(downsampleQuery(["a", "b"], { start: "-1h" }, 1599.6)).toEqual({ points: 1600, start: "-1h", end: undefined, signals: "a,b" });
    expect(downsampleQuery(["a"], {}, 1).points).toBe(2);
    expect(aggregateQuery(["a"], { start: "x", end: "y" }, "1m", "max")).toEqual({ bucket: "1m", fn: "max", start: "x", end: "y", signals: "a" });
  });

  it("plots numbers, integers and bools, not text", () => {
    expect(["integer", "number", "bool", "string", "mixed"].map((k) => isPlottable(k as never))).toEqual([true, true, true, false, false]);
  });

  it("finds each signal's last sample before a time: from /latest, else the last aggregate", async () => {
    const start = 1_800_000_000e9;
    const fetch = mockFetch((url) => {
      if (url.includes("/latest")) {
        return jsonResponse({
          values: { still: { time: start - 3600e9, value: true }, moved: { time: start + 5e9, value: 2 }, text: { time: 1, value: "on" } },
        });
      }
      return jsonResponse({ rows: [{ time: start - 60e9, values: { moved: { last: 1.5 } } }] });
    });
    const found = await lastBefore("crane", "telemetry", ["still", "moved", "text", "never"], start, 900);
    expect(found).toEqual({ still: { time: start - 3600e9, value: 1 }, moved: { time: start - 60e9, value: 1.5 } });
    const urls = fetch.mock.calls.map((c) => decodeURIComponent(String(c[0])));
    expect(urls[0]).toBe("/api/v1/twins/crane/streams/telemetry/latest?signals=still,moved,text,never");
    // Only the signal that changed since the start needs the second read, over 900 s before it.
    const end = start - 1000;
    expect(urls[1]).toBe(
      `/api/v1/twins/crane/streams/telemetry/aggregate?bucket=900s&fn=last&start=${end - 900e9}&end=${end}&signals=moved`,
    );
    expect(urls).toHaveLength(2);
  });
});
